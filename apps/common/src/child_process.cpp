#include "sarloc/app/child_process.hpp"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <thread>

#include "sarloc/app/shutdown_signal.hpp"
#include "sarloc/core/common/errors.hpp"

extern char** environ;

namespace sarloc::app {

ChildProcess::ChildProcess(std::string name, const std::vector<std::string>& argv, const std::string& log_path)
    : name_(std::move(name)) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  posix_spawn_file_actions_addclose(&actions, STDIN_FILENO);
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  // The child stops when we go (shutdown_signal.cpp: SARLOC_PARENT_PID), so a killed
  // launcher never leaves a mission running.
  const std::string assignment_prefix = std::string(kParentPidVariable) + "=";
  std::vector<std::string> env_storage{assignment_prefix + std::to_string(getpid())};
  for (char** e = environ; *e != nullptr; ++e) {
    if (std::strncmp(*e, assignment_prefix.c_str(), assignment_prefix.size()) != 0) env_storage.emplace_back(*e);
  }
  std::vector<char*> env;
  for (auto& e : env_storage) env.push_back(e.data());
  env.push_back(nullptr);
  const int rc = posix_spawn(&pid_, args[0], &actions, nullptr, args.data(), env.data());
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) throw Error("cannot start " + name_ + " (" + argv[0] + "): " + std::strerror(rc));
}

ChildProcess::~ChildProcess() {
  if (exit_code_ < 0) stop(std::chrono::seconds(5));
}

void ChildProcess::reap(bool block) {
  if (exit_code_ >= 0) return;
  int status = 0;
  pid_t r = -1;
  do {
    r = waitpid(pid_, &status, block ? 0 : WNOHANG);
  } while (r == -1 && errno == EINTR);  // a signal (a second Ctrl-C) must not leave a zombie
  if (r == pid_) {
    exit_code_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  } else if (r == -1 && errno == ECHILD) {
    exit_code_ = 255;  // reaped elsewhere: gone, status unknown
  }
}

bool ChildProcess::running() {
  reap(false);
  return exit_code_ < 0;
}

int ChildProcess::stop(std::chrono::milliseconds grace) {
  if (!running()) return exit_code_;
  ::kill(pid_, SIGTERM);
  const auto deadline = std::chrono::steady_clock::now() + grace;
  while (running() && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  if (running()) {
    ::kill(pid_, SIGKILL);
    reap(true);
  }
  return exit_code_;
}

void ChildProcess::kill_now() {
  if (!running()) return;
  ::kill(pid_, SIGKILL);
  reap(true);
}

}  // namespace sarloc::app
