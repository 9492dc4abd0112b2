#pragma once
// This process's CPU use and resident memory, from /proc (Linux), for NodeStatus.
namespace sarloc::dds {

class ProcessStats {
 public:
  ProcessStats();
  /// CPU time used since the previous call, as a percentage of one core.
  double cpu_percent();
  /// Resident set size in MiB.
  static double rss_mb();

 private:
  double last_cpu_s_ = 0.0;
  double last_wall_s_ = 0.0;
};

}  // namespace sarloc::dds
