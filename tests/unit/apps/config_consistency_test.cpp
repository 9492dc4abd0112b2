// One configuration (issue 58): the product, its daemon, its devices and the evaluation run the
// code's defaults of the estimator's sections (simulation:, sog:, search:). A shipped mission and
// the evaluation's reference config must not differ from them at all; any other evaluation config
// (Table I, the noise sweep) may differ only in keys it writes itself, so it says what it changes.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>

#include "eval_config.hpp"
#include "sarloc/app/avalanche_yaml.hpp"
#include "sarloc/app/mission_config.hpp"

namespace sarloc::app {
namespace {

namespace fs = std::filesystem;
using Parameters = std::map<std::string, std::string>;

const fs::path kSource = SARLOC_SOURCE_DIR;

std::vector<fs::path> yaml_files(const fs::path& dir) {
  std::vector<fs::path> out;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.path().extension() == ".yaml") out.push_back(entry.path());
  }
  std::sort(out.begin(), out.end());
  return out;
}

const Parameters& defaults() {
  static const Parameters d = avalanche_parameters({}, {}, {});
  return d;
}

/// Keys `load` reads that the file writes itself.
template <class Load>
std::set<std::string> written_keys(Load load) {
  YamlReader::ValueRecorder recorder;
  load();
  std::set<std::string> out;
  for (const auto& [key, value] : recorder.values()) {
    if (value.written) out.insert(key);
  }
  return out;
}

/// Every parameter of `run` that differs from the defaults and is not in `allowed`.
std::vector<std::string> unstated_differences(const Parameters& run, const std::set<std::string>& allowed) {
  std::vector<std::string> out;
  for (const auto& [key, value] : run) {
    const auto d = defaults().find(key);
    if (d == defaults().end()) {
      out.push_back(key + ": no such default");
    } else if (d->second != value && allowed.count(key) == 0) {
      out.push_back(key + " = " + value + " (default " + d->second + ")");
    }
  }
  return out;
}

std::string joined(const std::vector<std::string>& lines) {
  std::string out;
  for (const auto& l : lines) out += "\n  " + l;
  return out;
}

// The daemon (per sector), every device and the simulated sensors of every shipped mission run
// exactly the defaults.
TEST(ConfigConsistency, ShippedMissionsRunTheDefaults) {
  const auto files = yaml_files(kSource / "config/missions");
  ASSERT_GE(files.size(), 3U);
  for (const auto& f : files) {
    const MissionConfig mission = load_mission_config(f.string());
    std::vector<std::string> sectors = mission.sectors;
    if (sectors.empty()) sectors.push_back("");
    for (const auto& sector : sectors) {
      const auto& a = mission.core_config(sector).estimators.avalanche_rescuer;
      EXPECT_EQ(joined(unstated_differences(avalanche_parameters(mission.scenario.sensors, a.sog, a.search), {})), "")
          << f.filename() << ", sarloc-core of sector '" << sector << "' differs from the defaults";
    }
    for (const auto& r : mission.scenario.rescuers) {
      const auto& a = mission.rescuer_config(r.id).estimators.avalanche_rescuer;
      EXPECT_EQ(joined(unstated_differences(avalanche_parameters(mission.scenario.sensors, a.sog, a.search), {})), "")
          << f.filename() << ", the device of " << r.id << " differs from the defaults";
    }
  }
}

// The evaluation's reference config states trials, seeds and the budget, nothing else: its
// tables are the product's configuration. Every other evaluation config writes what it changes.
TEST(ConfigConsistency, EvaluationConfigsDifferOnlyWhereTheySaySo) {
  for (const auto& f : yaml_files(kSource / "config/eval")) {
    if (f.filename() == "firefighter.yaml") continue;  // sarloc-eval firefighter's, no avalanche sections
    avalanche::EvaluationSetup setup;
    const auto written = written_keys([&] { eval::load_avalanche_config(f.string(), setup); });
    const Parameters run = avalanche_parameters(setup.simulation, setup.sog, setup.search);
    const bool reference = f.filename() == "avalanche.yaml";
    EXPECT_EQ(joined(unstated_differences(run, reference ? std::set<std::string>{} : written)), "")
        << f.filename() << (reference ? " must run the defaults" : " differs from the defaults in keys it does not write");
    if (!reference) {
      // A written key equal to its default says nothing: keep the file to what it changes.
      for (const auto& key : written) {
        const auto d = defaults().find(key);
        if (d != defaults().end()) {
          EXPECT_NE(run.at(key), d->second) << f.filename() << ": " << key << " repeats its default";
        }
      }
    }
  }
}

// The comparison itself: a changed parameter shows, under its key, and only when it differs.
TEST(ConfigConsistency, ParametersShowEveryChangeUnderItsKey) {
  avalanche::SimulationConfig sim;
  avalanche::SogConfig sog;
  avalanche::SearchConfig search;
  search.opening_line_samples += 1;
  sim.receiver.kind = sim.receiver.kind == avalanche::ReceiverKind::kIdeal ? avalanche::ReceiverKind::kRealistic
                                                                          : avalanche::ReceiverKind::kIdeal;
  sog.noise_floor_A_per_m *= 1.0 + 1e-15;
  const auto diff = unstated_differences(avalanche_parameters(sim, sog, search), {});
  ASSERT_EQ(diff.size(), 3U) << joined(diff);
  EXPECT_EQ(diff[0].rfind("search.opening_line_samples = ", 0), 0U) << diff[0];
  EXPECT_EQ(diff[1].rfind("simulation.receiver.kind = ", 0), 0U) << diff[1];
  EXPECT_EQ(diff[2].rfind("sog.noise_floor_A_per_m = ", 0), 0U) << diff[2];
  EXPECT_GT(defaults().size(), 100U) << "every key of the three sections";
  EXPECT_TRUE(unstated_differences(avalanche_parameters(sim, sog, search), {"search.opening_line_samples",
                                                                           "simulation.receiver.kind",
                                                                           "sog.noise_floor_A_per_m"})
                  .empty());
}

// Issue 61: the receiver's height above the snow is one fact. Set under any of its three keys, it
// is what the simulated rescuers do, what the filter assumes and what incident command assumes
// (two keys that disagree are refused: tests/config/invalid/*/antenna_heights_disagree.yaml).
TEST(ConfigConsistency, TheReceiverHeightSetOnceIsHandedToEveryConsumer) {
  const fs::path file = fs::path(::testing::TempDir()) / "one-antenna-height.yaml";
  for (const std::string section : {"simulation", "sog", "command"}) {
    std::ofstream(file) << section << ": {antenna_height_m: 1.3}\n"
                        << "victims:\n  - {name: A, position: [0.0, 30.0, -1.0], moment: [0.01, 0.0, 0.005]}\n"
                        << "rescuers:\n  - {id: r1, team: t, start: [0.0, 0.0]}\n";
    const auto mission = load_mission_config(file.string());
    EXPECT_EQ(mission.scenario.sensors.antenna_height_m, 1.3) << section;
    EXPECT_EQ(mission.estimators.avalanche_rescuer.sog.antenna_height_m, 1.3) << section;
    EXPECT_EQ(mission.core_config("").estimators.avalanche_rescuer.sog.antenna_height_m, 1.3) << section;
    EXPECT_EQ(mission.command_config().incident.antenna_height_m, 1.3) << section;
  }
  fs::remove(file);
}

}  // namespace
}  // namespace sarloc::app
