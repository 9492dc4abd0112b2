// sarloc-command: the incident-command aggregator. Fuses every rescuer's victim estimates in
// the incident frame, tracks responders by team, publishes the incident picture
// (TRANSIENT_LOCAL: a dashboard that subscribes late gets the current state at once).
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include <fstream>

#include "sarloc/app/logging.hpp"
#include "sarloc/app/mission_config.hpp"
#include "sarloc/app/run_main.hpp"
#include "sarloc/app/shutdown_signal.hpp"

int main(int argc, char** argv) {
  using namespace sarloc;
  app::install_shutdown_handlers();
  CLI::App cli{"sarloc-command: incident-command aggregator (fused victims, team accountability)"};
  std::string config_path;
  std::string log_level = "info";
  std::string summary_path;
  std::int64_t epoch_ns = 0;
  int domain = -1;
  cli.add_option("-c,--config", config_path, "mission YAML (config/missions/default.yaml)")->required();
  cli.add_option("--epoch-ns", epoch_ns, "mission start, ns since the Unix epoch (sarloc-mission sets it; default now)");
  cli.add_option("--summary", summary_path, "write the final picture as JSON here on exit");
  cli.add_option("--domain", domain, "DDS domain id, overriding dds.domain_id of the config");
  cli.add_option("--log-level", log_level, "trace, debug, info, warn, error, critical, off");
  cli.set_version_flag("--version", SARLOC_VERSION);
  CLI11_PARSE(cli, argc, argv);

  return app::run_main("sarloc-command", [&] {
    app::setup_logging(log_level, "command");
    const auto mission = app::load_mission_config(config_path);
    const TimestampNs epoch = epoch_ns > 0 ? epoch_ns : sarloc::dds::MissionClock::wall_now_ns();
    auto node_config = mission.command_config();
    auto dds_config = mission.dds;
    if (domain >= 0) dds_config.domain_id = static_cast<std::uint32_t>(domain);
    dds_config.name = node_config.node_id;
    auto participant = std::make_shared<sarloc::dds::Participant>(dds_config);
    sarloc::dds::CommandNode node(participant, node_config, sarloc::dds::MissionClock(epoch, mission.speedup));
    spdlog::info("{} running for incident '{}'", node_config.node_id, node_config.incident_id);
    std::size_t last_count = 0;
    while (!app::wait_for_shutdown(std::chrono::seconds(1))) {
      const auto victims = node.victims();
      if (victims.size() != last_count) {
        spdlog::info("incident picture: {} victim(s)", victims.size());
        last_count = victims.size();
      }
    }
    if (!summary_path.empty()) {
      nlohmann::json j;
      j["victims"] = nlohmann::json::array();
      for (const auto& v : node.victims()) {
        j["victims"].push_back({{"victim_id", v.victim_id},
                                {"position", {v.position.position.x(), v.position.position.y(), v.position.position.z()}},
                                {"state", static_cast<int>(v.state)},
                                {"sources", v.sources.size()}});
      }
      j["teams"] = nlohmann::json::array();
      for (const auto& t : node.teams()) {
        for (const auto& m : t.members) {
          j["teams"].push_back({{"team_id", t.team_id},
                                {"responder_id", m.responder_id},
                                {"link", static_cast<int>(m.link)},
                                {"accountability", static_cast<int>(m.accountability)}});
        }
      }
      std::ofstream(summary_path) << j.dump(2) << "\n";
    }
    return app::ExitCode::kOk;
  });
}
