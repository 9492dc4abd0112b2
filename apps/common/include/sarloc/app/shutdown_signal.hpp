#pragma once
// SIGINT/SIGTERM handling installed before start-up: the handler only sets a flag; main
// threads poll it or wait on it, so shutdown runs in normal code, never in a signal handler.
#include <chrono>
#include <string_view>

namespace sarloc::app {

/// Environment variable through which ChildProcess passes its pid to the child.
inline constexpr std::string_view kParentPidVariable = "SARLOC_PARENT_PID";

/// Installs handlers for SIGINT and SIGTERM (idempotent). A process started by ChildProcess
/// also stops when its launcher dies.
void install_shutdown_handlers();

/// True once SIGINT or SIGTERM arrived (or request_shutdown() was called).
bool shutdown_requested();

/// The signal number that asked for shutdown, 0 if none.
int shutdown_signal();

/// Ask for shutdown from code (tests, a --duration limit).
void request_shutdown();

/// Sleeps until shutdown is requested or `timeout` passes; returns shutdown_requested().
bool wait_for_shutdown(std::chrono::milliseconds timeout);

}  // namespace sarloc::app
