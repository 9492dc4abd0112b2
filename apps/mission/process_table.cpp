#include "process_table.hpp"

#include <spdlog/spdlog.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <thread>

#include "sarloc/app/floor_plan_imdf.hpp"
#include "sarloc/app/floor_plan_yaml.hpp"
#include "sarloc/core/common/errors.hpp"

namespace sarloc::app {
namespace fs = std::filesystem;

ProcessTable::ProcessTable(const MissionConfig& mission, ProcessTableConfig config)
    : mission_(mission), config_(std::move(config)), command_killed_(mission.command_instances(), false) {
  commands_.resize(mission.command_instances());
  if (config_.hosts.empty()) return;
  if (config_.launcher.empty()) throw ConfigError("--host given without --launcher: nothing can start a process on a host");
  const auto names = placeable_names(mission);
  for (const auto& [name, host] : config_.hosts) {
    if (names.count(name) == 0) throw ConfigError("--host " + name + "=" + host + ": no process '" + name + "' in this mission");
    if (host.empty()) throw ConfigError("--host " + name + "=: empty host");
  }
}

ProcessTable::~ProcessTable() {
  stop_devices();
  stop_the_rest(0);
}

std::set<std::string> ProcessTable::placeable_names(const MissionConfig& mission) {
  std::set<std::string> names;
  if (mission.sectors.empty()) names.insert("core");
  for (const auto& sector : mission.sectors) names.insert("core-" + sector);
  const unsigned instances = mission.command_instances();
  for (unsigned k = 1; k <= instances; ++k) names.insert(instances == 1 ? "command" : "command-" + std::to_string(k));
  for (const auto& r : mission.scenario.rescuers) names.insert("rescuer-" + r.id);
  for (const auto& f : mission.firefighters) names.insert("rescuer-" + f.id);
  return names;
}

std::vector<std::string> ProcessTable::programs(bool dashboard) {
  std::vector<std::string> names{"sarloc-core", "sarloc-rescuer", "sarloc-command", "sarloc-record"};
  if (dashboard) names.push_back("sarloc-dashboard");
  return names;
}

std::string ProcessTable::log_file(const std::string& name) const { return (config_.run_dir / (name + ".log")).string(); }

std::vector<std::string> ProcessTable::common_args(const std::string& program) const {
  return {(config_.bin_dir / program).string(), "-c", config_.mission_file, "--domain", std::to_string(config_.domain_id),
          "--log-level", config_.log_level};
}

std::unique_ptr<ChildProcess> ProcessTable::start(const std::string& name, const std::string& placed_as,
                                                  std::vector<std::string> args) {
  // A process placed on a host (--host) starts through the launcher; the others here.
  if (const auto it = config_.hosts.find(placed_as); it != config_.hosts.end()) {
    args.insert(args.begin(), {config_.launcher, it->second});
  }
  return std::make_unique<ChildProcess>(name, args, log_file(name));
}

void ProcessTable::start_recorder(const std::string& recording_path) {
  auto args = common_args("sarloc-record");
  args.insert(args.end(), {"-o", recording_path, "--meta", "epoch_ns=" + std::to_string(config_.epoch_ns), "--meta",
                           "speedup=" + std::to_string(mission_.speedup), "--meta-file",
                           "mission_yaml=" + config_.mission_file});
  if (!mission_.building_path.empty()) {
    std::string plan_file = mission_.building_path;
    if (app::is_imdf_directory(plan_file)) {
      // An IMDF directory is no file to attach: the recording carries the plan as it was read.
      plan_file = (config_.run_dir / "building_plan.yaml").string();
      std::ofstream(plan_file) << app::floor_plan_yaml_text(app::load_floor_plan(mission_.building_path));
    }
    args.insert(args.end(), {"--meta-file", "building_plan_yaml=" + plan_file});
  }
  recorder_ = start("record", "record", args);
}

void ProcessTable::start_dashboard(int port) {
  const fs::path url_file = config_.run_dir / "dashboard.url";
  fs::remove(url_file);
  auto args = common_args("sarloc-dashboard");
  args.insert(args.end(), {"--epoch-ns", std::to_string(config_.epoch_ns), "--url-file", url_file.string()});
  if (port >= 0) args.insert(args.end(), {"--port", std::to_string(port)});
  if (port == 0) args.insert(args.end(), {"--foxglove-port", "0"});  // any free port for both
  dashboard_ = start("dashboard", "dashboard", args);
  for (int k = 0; k < 50 && !fs::exists(url_file) && dashboard_->running(); ++k) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  std::ifstream url(url_file);
  std::string text, feed;
  if (url && std::getline(url, text)) {
    std::printf("dashboard: %s\n", text.c_str());
    if (std::getline(url, feed) && !feed.empty()) std::printf("Foxglove / Lichtblick: %s\n", feed.c_str());
    std::fflush(stdout);
  } else {
    spdlog::error("the dashboard did not start: see {}", log_file("dashboard"));
  }
}

void ProcessTable::start_cores(const std::string& suffix) {
  cores_.clear();
  const auto sectors = mission_.sectors.empty() ? std::vector<std::string>{""} : mission_.sectors;
  for (const auto& sector : sectors) {
    auto args = common_args("sarloc-core");
    if (!sector.empty()) args.insert(args.end(), {"--sector", sector});
    const std::string placed_as = sector.empty() ? "core" : "core-" + sector;
    cores_.push_back(start(placed_as + suffix, placed_as, args));
  }
}

std::string ProcessTable::command_name(unsigned instance) const {
  return commands_.size() == 1 ? std::string("command") : "command-" + std::to_string(instance);
}

void ProcessTable::start_command(unsigned instance, const std::string& suffix) {
  const std::string name = command_name(instance) + suffix;
  auto args = common_args("sarloc-command");
  args.insert(args.end(), {"--instance", std::to_string(instance), "--epoch-ns", std::to_string(config_.epoch_ns),
                           "--summary", (config_.run_dir / (name + ".json")).string()});
  commands_.at(instance - 1) = start(name, command_name(instance), args);
  command_killed_.at(instance - 1) = false;
}

void ProcessTable::start_devices() {
  // Avalanche rescuers and firefighters: the same app; a firefighter's ends when its simulated
  // search does, quietly.
  std::vector<std::pair<std::string, bool>> devices;
  for (const auto& r : mission_.scenario.rescuers) devices.emplace_back(r.id, false);
  for (const auto& f : mission_.firefighters) devices.emplace_back(f.id, true);
  std::filesystem::remove(config_.run_dir / kSimWorldFile);  // a reused run folder's old digs
  for (const auto& [id, quiet] : devices) {
    auto args = common_args("sarloc-rescuer");
    args.insert(args.end(), {"--id", id, "--epoch-ns", std::to_string(config_.epoch_ns), "--summary",
                             (config_.run_dir / (id + ".json")).string()});
    if (quiet) {
      args.push_back("--quiet");
    } else {  // an avalanche rescuer: its digs silence transmitters for every device at once
      args.insert(args.end(), {"--sim-world", (config_.run_dir / kSimWorldFile).string()});
    }
    devices_[id] = start("rescuer-" + id, "rescuer-" + id, args);
  }
}

void ProcessTable::kill_cores() {
  for (auto& c : cores_) c->kill_now();
}

void ProcessTable::kill_command(unsigned instance) {
  commands_.at(instance - 1)->kill_now();
  command_killed_.at(instance - 1) = true;
}

void ProcessTable::kill_device(const std::string& id) { devices_.at(id)->kill_now(); }

bool ProcessTable::any_command_running() {
  return std::any_of(commands_.begin(), commands_.end(), [](auto& c) { return c && c->running(); });
}

bool ProcessTable::a_command_failed() {
  bool failed = false;
  for (std::size_t k = 0; k < commands_.size(); ++k) {
    if (command_killed_[k] || !commands_[k] || commands_[k]->running()) continue;
    spdlog::error("{} exited unexpectedly (code {}); see {}", commands_[k]->name(), commands_[k]->exit_code(),
                  log_file(commands_[k]->name()));
    failed = true;
  }
  return failed;
}

std::vector<std::string> ProcessTable::stop_devices() {
  std::vector<std::string> stopped_in_order;
  for (auto& [id, device] : devices_) {
    if (device->running()) stopped_in_order.push_back(id);
    device->stop(std::chrono::seconds(10));
  }
  devices_.clear();
  return stopped_in_order;
}

bool ProcessTable::stop_the_rest(unsigned active) {
  // Standby instances before the active one, which they would otherwise take over from.
  for (std::size_t k = 0; k < commands_.size(); ++k) {
    if (commands_[k] && k + 1 != active) commands_[k]->stop(std::chrono::seconds(10));
  }
  if (active > 0 && commands_.at(active - 1)) commands_[active - 1]->stop(std::chrono::seconds(10));
  for (auto& c : cores_) c->stop(std::chrono::seconds(10));
  if (dashboard_) dashboard_->stop(std::chrono::seconds(5));
  bool clean = true;
  if (recorder_) {
    const int code = recorder_->stop(std::chrono::seconds(20));
    if (code != 0) {
      spdlog::error("the recorder ended with exit code {}: see {}; the recording may need sarloc-record --recover", code,
                    log_file("record"));
      clean = false;
    }
  }
  for (auto& c : commands_) c.reset();
  cores_.clear();
  dashboard_.reset();
  recorder_.reset();
  return clean;
}

}  // namespace sarloc::app
