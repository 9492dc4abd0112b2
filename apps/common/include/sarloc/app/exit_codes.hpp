#pragma once
// Exit codes shared by every sarloc executable (docs/operations.md lists them).

namespace sarloc::app {

enum class ExitCode : int {
  kOk = 0,            ///< ran and succeeded (mission: every victim found; eval: targets met)
  kFailure = 1,       ///< ran to the end but the outcome failed (victim not found, target missed)
  kUsage = 2,         ///< bad command line
  kConfig = 3,        ///< configuration file missing or invalid
  kRuntime = 4,       ///< could not run (DDS participant creation, I/O, child process)
  kInterrupted = 130, ///< stopped by SIGINT/SIGTERM before finishing
};

inline int to_int(ExitCode code) { return static_cast<int>(code); }

}  // namespace sarloc::app
