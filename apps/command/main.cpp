// sarloc-command: the incident-command aggregator. Fuses every rescuer's victim estimates in
// the incident frame, tracks responders by team, publishes the incident picture
// (TRANSIENT_LOCAL: a dashboard that subscribes late gets the current state at once).
// An incident runs command.instances of it (--instance 1, 2, ...): one publishes, the others
// stand by with the same picture and take over when it is lost (docs/operations.md).
#include <CLI/CLI.hpp>
#include <map>
#include <string>
#include <spdlog/spdlog.h>

#include "sarloc/app/command_line.hpp"
#include "sarloc/app/json_io.hpp"
#include "sarloc/app/logging.hpp"
#include "sarloc/app/node_options.hpp"
#include "sarloc/app/run_main.hpp"
#include "sarloc/app/shutdown_signal.hpp"

namespace {

void write_summary(const sarloc::dds::CommandNode& node, const std::string& path) {
  nlohmann::json j;
  j["victims"] = nlohmann::json::array();
  for (const auto& v : node.victims()) j["victims"].push_back(sarloc::app::to_json(v));
  j["teams"] = sarloc::app::to_json(node.teams());
  j["role"] = sarloc::incident::to_string(node.role());
  sarloc::app::write_json_file(path, j);
}

}  // namespace

int main(int argc, char** argv) {
  using namespace sarloc;
  app::install_shutdown_handlers();
  CLI::App cli{"sarloc-command: incident-command aggregator (fused victims, team accountability)"};
  app::NodeOptions options;
  std::string summary_path;
  unsigned instance = 1;
  app::add_node_options(cli, options);
  cli.add_option("--summary", summary_path, "write the final picture as JSON here on exit");
  cli.add_option("--instance", instance, "which of the command.instances this is (1 claims first)")
      ->capture_default_str();
  if (auto code = app::parse_command_line(cli, argc, argv)) return *code;

  return app::run_main("sarloc-command", [&] {
    app::setup_logging(options.log_level, "command");
    const auto mission = app::load_mission_config(options.config_path);
    const auto node_config = mission.command_config(instance);
    node_config.validate();  // --instance within command.instances
    auto participant = std::make_shared<sarloc::dds::Participant>(
        options.participant(mission, node_config.node_id, node_config.node_id));
    sarloc::dds::CommandNode node(participant, node_config, options.clock(mission));
    spdlog::info("{} running for incident '{}' (instance {} of {})", node_config.node_id, node_config.incident.incident_id,
                 instance, node_config.incident.standby.instances);
    std::size_t last_count = 0;
    // A line per victim whose state or doubt changed, with the sources behind it: enough to
    // trace afterwards which rescuers' signals confirmed what.
    std::map<std::uint32_t, std::pair<incident::VictimState, std::uint32_t>> last_said;
    while (!app::wait_for_shutdown(std::chrono::seconds(1))) {
      const auto victims = node.victims();
      if (victims.size() != last_count) {
        spdlog::info("incident picture: {} victim(s)", victims.size());
        last_count = victims.size();
      }
      for (const auto& v : victims) {
        const std::pair<incident::VictimState, std::uint32_t> now{v.state, v.possibly_same_as};
        const auto said = last_said.find(v.victim_id);
        if (said != last_said.end() && said->second == now) continue;
        last_said[v.victim_id] = now;
        std::string sources;
        for (const auto& s : v.sources) sources += " " + s.rescuer_id + "/" + std::to_string(s.signal_id);
        const std::string doubt = v.possibly_same_as != 0 ? ", possibly the same as victim " + std::to_string(v.possibly_same_as) : "";
        spdlog::info("victim {}: {}{} at ({:.1f}, {:.1f}, {:.1f}), sources:{}", v.victim_id, incident::to_string(v.state), doubt,
                     v.position.position.x(), v.position.position.y(), v.position.position.z(), sources.empty() ? " none" : sources);
      }
    }
    if (!summary_path.empty()) write_summary(node, summary_path);
    node.sign_off(std::chrono::seconds(1));  // stopped in order, not lost
    return app::ExitCode::kOk;
  });
}
