#pragma once
// Step-by-step traces of evaluation trials (sarloc-eval avalanche --trace-trial / --trace-csv,
// sarloc-eval multi-burial --trace-trial).
//
// The CSV has one row per step of every trial, in trial order, with the truth beside what the
// filter believed: enough to replay the measurements offline (scripts/ideal-bearing-check
// compares the SOG posterior with a brute-force Bayesian grid on the same path).
#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include "sarloc/core/avalanche/evaluation.hpp"
#include "sarloc/core/avalanche/multi_burial.hpp"

namespace sarloc::eval {

/// One human-readable line per step (stdout).
void print_trace_step(const avalanche::TrialStep& s);

/// One multiple-burial trial (sarloc-eval multi-burial --trace-trial): the victims, then per
/// step a line for the rescuer and one per sample processed (stdout).
avalanche::MultiBurialTraceObserver multi_burial_trace_printer();

/// Collects CSV rows from worker threads and writes them in trial order.
class TraceCsv {
 public:
  explicit TraceCsv(std::uint32_t trials) : rows_(trials) {}
  /// Thread-safe for distinct trials (each trial has its own buffer).
  void add(const avalanche::TrialStep& s);
  void write(std::ostream& out) const;
  static const char* header();

 private:
  std::vector<std::string> rows_;
};

}  // namespace sarloc::eval
