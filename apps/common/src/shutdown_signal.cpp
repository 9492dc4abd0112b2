#include "sarloc/app/shutdown_signal.hpp"

#include <sys/prctl.h>
#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <string>
#include <csignal>
#include <thread>

namespace sarloc::app {
namespace {

std::atomic<int> g_signal{0};
std::atomic<bool> g_requested{false};

extern "C" void on_signal(int sig) {
  g_signal.store(sig);
  g_requested.store(true);
}

}  // namespace

void install_shutdown_handlers() {
  struct sigaction action {};
  action.sa_handler = on_signal;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  // Started by a launcher (ChildProcess sets SARLOC_PARENT_PID): get SIGTERM when it dies, and
  // stop at once if it is already gone, so no mission process outlives its launcher.
  if (const char* parent = std::getenv(kParentPidVariable.data())) {
    prctl(PR_SET_PDEATHSIG, SIGTERM);
    if (std::to_string(getppid()) != parent) request_shutdown();
  }
}

bool shutdown_requested() { return g_requested.load(); }

int shutdown_signal() { return g_signal.load(); }

void request_shutdown() { g_requested.store(true); }

bool wait_for_shutdown(std::chrono::milliseconds timeout) {
  // Polling in 20 ms slices: a signal handler cannot portably notify a condition variable.
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (!g_requested.load() && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return g_requested.load();
}

}  // namespace sarloc::app
