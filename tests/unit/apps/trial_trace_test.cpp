#include "trial_trace.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

namespace sarloc::eval {
namespace {

std::vector<std::string> split(const std::string& line, char sep) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  for (std::string cell; std::getline(ss, cell, sep);) out.push_back(cell);
  return out;
}

// Rows come out in trial order whatever thread ran which trial, one per step, each with every
// header column; the first row of a trial is taken at the start pose.
TEST(TraceCsvTest, OneRowPerStepInTrialOrder) {
  avalanche::EvaluationSetup setup;
  setup.simulation.receiver.kind = avalanche::ReceiverKind::kIdeal;  // a sample every step
  setup.sog.initial_components = 400;
  setup.evaluation.trials = 3;
  setup.evaluation.threads = 2;
  setup.evaluation.seed = 99;
  TraceCsv csv(setup.evaluation.trials);
  const auto summary = avalanche::run_evaluation(
      setup, {}, {}, [&csv](const avalanche::TrialStep& s) { csv.add(s); });
  std::stringstream out;
  csv.write(out);

  std::string line;
  ASSERT_TRUE(std::getline(out, line));
  const std::vector<std::string> header = split(line, ',');
  EXPECT_EQ(line + "\n", TraceCsv::header());
  std::vector<std::vector<std::string>> rows;
  while (std::getline(out, line)) rows.push_back(split(line, ','));

  std::size_t expected = 0;
  for (const auto& t : summary.per_trial) expected += t.steps;
  ASSERT_EQ(rows.size(), expected);
  std::size_t i = 0;
  for (std::uint32_t trial = 0; trial < 3; ++trial) {
    double mass_at_20m = -1.0;
    for (std::uint32_t step = 1; step <= summary.per_trial[trial].steps; ++step, ++i) {
      ASSERT_EQ(rows[i].size(), header.size()) << "row " << i;
      EXPECT_EQ(std::stoul(rows[i][0]), trial);
      EXPECT_EQ(std::stoul(rows[i][1]), step);
      if (step == 1) {
        EXPECT_DOUBLE_EQ(std::stod(rows[i][6]), 0.0);  // rx_w: the walk starts at the origin
        EXPECT_DOUBLE_EQ(std::stod(rows[i][8]), setup.simulation.antenna_height_m);
      }
      const double dx = std::stod(rows[i][3]) - std::stod(rows[i][6]);
      const double dy = std::stod(rows[i][4]) - std::stod(rows[i][7]);
      if (mass_at_20m < 0.0 && std::hypot(dx, dy) < 20.0) mass_at_20m = std::stod(rows[i][20]);
    }
    // 20 m out the posterior bearing has converged on the truth (columns are the truth's).
    EXPECT_GT(mass_at_20m, 0.9) << "trial " << trial;
    // The last step's error and NEES are the ones the evaluation scored.
    const std::vector<std::string>& last = rows[i - 1];
    const auto column = [&header](const std::string& name) {
      return static_cast<std::size_t>(std::find(header.begin(), header.end(), name) - header.begin());
    };
    const double err = std::hypot(std::stod(last[column("err_x_r")]), std::stod(last[column("err_y_r")]),
                                  std::stod(last[column("err_z_r")]));
    EXPECT_NEAR(err, summary.per_trial[trial].error_m, 1e-3) << "trial " << trial;
    EXPECT_NEAR(std::stod(last[column("nees")]), summary.per_trial[trial].final_nees,
                1e-3 * (1.0 + summary.per_trial[trial].final_nees))
        << "trial " << trial;
  }
}

}  // namespace
}  // namespace sarloc::eval
