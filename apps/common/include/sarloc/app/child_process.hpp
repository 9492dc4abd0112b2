#pragma once
// A child process (sarloc-mission, benchmarks): started with posix_spawn, output to a log file, stopped
// with SIGTERM (then SIGKILL after a grace period). Never leaves a process behind: the
// destructor stops it.
#include <sys/types.h>

#include <chrono>
#include <string>
#include <vector>

namespace sarloc::app {

class ChildProcess {
 public:
  ChildProcess(std::string name, const std::vector<std::string>& argv, const std::string& log_path);
  ~ChildProcess();
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  const std::string& name() const { return name_; }
  pid_t pid() const { return pid_; }
  /// True while it runs (reaps it when it has exited).
  bool running();
  /// Exit status once it has exited (-1 while running; 128+signal when killed).
  int exit_code() const { return exit_code_; }
  /// SIGTERM, wait up to `grace`, then SIGKILL. Returns the exit code.
  int stop(std::chrono::milliseconds grace);
  /// SIGKILL at once (fault injection).
  void kill_now();

 private:
  void reap(bool block);

  std::string name_;
  pid_t pid_ = -1;
  int exit_code_ = -1;
};

}  // namespace sarloc::app
