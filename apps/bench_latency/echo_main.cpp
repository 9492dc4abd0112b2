// sarloc-bench-echo: the raw DDS echo that sarloc-bench-latency compares sarloc-core with
// (echo_node.hpp). Same participant, topics and QoS profiles as the daemon; no estimation.
// Runs until SIGINT/SIGTERM (or its launcher's exit).
#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include "echo_node.hpp"
#include "sarloc/app/command_line.hpp"
#include "sarloc/app/logging.hpp"
#include "sarloc/app/node_options.hpp"
#include "sarloc/app/run_main.hpp"
#include "sarloc/app/shutdown_signal.hpp"

int main(int argc, char** argv) {
  using namespace sarloc;
  app::install_shutdown_handlers();
  CLI::App cli{"sarloc-bench-echo: answers every FieldMeasurement with a VictimEstimate at once (latency baseline)"};
  app::NodeOptions options;
  std::string handoff = "listener";
  app::add_node_options(cli, options, /*with_epoch=*/false);
  cli.add_option("--handoff", handoff,
                 "listener: answer on the DDS listener thread; queue: through a worker thread, as sarloc-core; waitset: a worker waiting in a DDS WaitSet")
      ->capture_default_str();
  if (auto code = app::parse_command_line(cli, argc, argv)) return *code;

  return app::run_main("sarloc-bench-echo", [&] {
    app::setup_logging(options.log_level, "echo");
    const auto mission = app::load_mission_config(options.config_path);
    bench::EchoNodeConfig config;
    config.handoff = bench::parse_echo_handoff(handoff);
    config.partitions = mission.core_config("").partitions;  // where the daemon would listen
    auto participant =
        std::make_shared<sarloc::dds::Participant>(options.participant(mission, config.node_id, config.node_id));
    bench::EchoNode node(participant, config);
    while (!app::wait_for_shutdown(std::chrono::milliseconds(200))) {
    }
    spdlog::info("{} stopping: {} echoed, {} refused by DDS", config.node_id, node.echoed(), node.refused());
    return app::ExitCode::kOk;
  });
}
