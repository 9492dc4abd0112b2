// sarloc-core: the localization core daemon. One DDS participant for the whole daemon; one
// SOG filter per (rescuer, signal) on a worker pool; publishes VictimEstimate and Guidance.
#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include "sarloc/app/command_line.hpp"
#include "sarloc/app/logging.hpp"
#include "sarloc/app/node_options.hpp"
#include "sarloc/app/run_main.hpp"
#include "sarloc/app/shutdown_signal.hpp"

int main(int argc, char** argv) {
  using namespace sarloc;
  app::install_shutdown_handlers();
  CLI::App cli{"sarloc-core: localization core daemon (one SOG filter per rescuer and signal)"};
  app::NodeOptions options;
  std::string sector;
  double duration_s = 0.0;
  app::add_node_options(cli, options, /*with_epoch=*/false);  // the daemon keeps no mission clock
  cli.add_option("--sector", sector, "serve only this sector's rescuers (a name under sectors:)");
  cli.add_option("--duration", duration_s, "stop after this many wall seconds (0 = until SIGINT/SIGTERM)");
  if (auto code = app::parse_command_line(cli, argc, argv)) return *code;

  return app::run_main("sarloc-core", [&] {
    app::setup_logging(options.log_level, sector.empty() ? "core" : "core-" + sector);
    const auto mission = app::load_mission_config(options.config_path);
    if (!sector.empty() && std::find(mission.sectors.begin(), mission.sectors.end(), sector) == mission.sectors.end()) {
      throw ConfigError("--sector = '" + sector + "': not one of the mission's sectors");
    }
    auto node_config = mission.core_config(sector);
    const auto dds_config = options.participant(mission, node_config.node_id, node_config.node_id);
    auto participant = std::make_shared<sarloc::dds::Participant>(dds_config);
    sarloc::dds::CoreNode node(participant, node_config);
    spdlog::info("{} running on domain {} (profile {})", node_config.node_id, dds_config.domain_id, dds_config.profile);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(duration_s);
    while (!app::shutdown_requested()) {
      app::wait_for_shutdown(std::chrono::milliseconds(200));
      if (duration_s > 0.0 && std::chrono::steady_clock::now() >= deadline) break;
    }
    const auto counters = node.counters();
    spdlog::info("{} stopping: {} samples accepted, {} rejected, {} rescuers served", node_config.node_id,
                 counters.accepted, counters.rejected, node.rescuers_served());
    node.sign_off(std::chrono::seconds(1));  // stopped in order: the devices hear a stop, not a loss
    return app::ExitCode::kOk;
  });
}
