// sarloc-bench-dashboard: an incident's picture at scale for the dashboard (docs/operations/
// dashboard.md, "Scale"): N responders in teams of 20 moving at 1 Hz, their TeamStatus, and
// M fused victims updated at 1 Hz, each stamped with the wall time it is published, so that the
// page can measure how old each sample is when the browser has it.
//
// Exit codes: 0 published for --seconds; 2 bad command line; 3 bad options; 4 DDS.
#include <CLI/CLI.hpp>

#include <chrono>
#include <cmath>
#include <thread>

#include "sarloc/app/command_line.hpp"
#include "sarloc/app/logging.hpp"
#include "sarloc/app/node_options.hpp"
#include "sarloc/app/run_main.hpp"
#include "sarloc/app/shutdown_signal.hpp"
#include "sarloc/dds/conversions.hpp"
#include "sarloc/dds/mission_clock.hpp"
#include "sarloc/dds/writer.hpp"

int main(int argc, char** argv) {
  using namespace sarloc;
  app::install_shutdown_handlers();
  CLI::App cli{"sarloc-bench-dashboard: an incident picture at scale (responders, teams, victims at 1 Hz)"};
  app::NodeOptions options;
  app::add_node_options(cli, options, false);
  int responders = 200, victims = 20;
  double seconds = 60.0;
  cli.add_option("--responders", responders, "responders, in teams of 20")->capture_default_str();
  cli.add_option("--victims", victims, "fused victims")->capture_default_str();
  cli.add_option("--seconds", seconds, "how long to publish")->capture_default_str();
  if (auto code = app::parse_command_line(cli, argc, argv)) return *code;
  return app::run_main("sarloc-bench-dashboard", [&] {
    app::setup_logging(options.log_level, "bench");
    if (responders < 1 || responders > 2000 || victims < 0 || victims > 500) throw ConfigError("--responders 1-2000, --victims 0-500");
    const auto mission = app::load_mission_config(options.config_path);
    auto participant =
        std::make_shared<sarloc::dds::Participant>(options.participant(mission, "bench-dashboard", "bench-dashboard"));
    sarloc::dds::Writer<::sarloc::ResponderPosition> positions(participant, sarloc::dds::device_position_options());
    sarloc::dds::Writer<::sarloc::TeamStatus> teams(participant);
    sarloc::dds::Writer<::sarloc::FusedVictim> fused(participant);
    const auto start = std::chrono::steady_clock::now();
    for (int tick = 0; !app::shutdown_requested(); ++tick) {
      if (std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() > seconds) break;
      std::map<int, incident::TeamStatus> by_team;
      for (int r = 0; r < responders; ++r) {
        responder::ResponderPosition p;
        p.responder_id = "resp-" + std::to_string(r);
        p.team_id = "team-" + std::to_string(r / 20);
        p.stamp = sarloc::dds::MissionClock::wall_now_ns();
        const double angle = 0.05 * tick + r;
        p.position.position = Vec3(10.0 * (r % 20) + 3.0 * std::cos(angle), 10.0 * (r / 20) + 3.0 * std::sin(angle), 0.0);
        p.position.covariance = Mat3::Identity() * 0.25;
        p.source = responder::PositionSource::kGnss;
        positions.write(sarloc::dds::to_idl(p));
        auto& team = by_team[r / 20];
        team.team_id = p.team_id;
        team.stamp = p.stamp;
        incident::MemberStatus m;
        m.responder_id = p.responder_id;
        m.last_position = p.position;
        m.last_seen = p.stamp;
        team.members.push_back(m);
      }
      for (const auto& [k, team] : by_team) teams.write(sarloc::dds::to_idl(team));
      for (int v = 1; v <= victims; ++v) {
        incident::FusedVictim f;
        f.victim_id = static_cast<std::uint32_t>(v);
        f.position.position = Vec3(7.0 * v, 50.0 + std::sin(0.1 * tick + v), -1.0);
        f.position.covariance = Mat3::Identity() * 0.3;
        f.state = v % 3 == 0 ? incident::VictimState::kFound : incident::VictimState::kLocated;
        f.first_seen = f.last_update = sarloc::dds::MissionClock::wall_now_ns();
        f.sources = {{"resp-" + std::to_string(v), 1, f.last_update, responder::SignalEvent::kNone, 0}};
        fused.write(sarloc::dds::to_idl(f));
      }
      std::this_thread::sleep_until(start + std::chrono::seconds(tick + 1));
    }
    return app::ExitCode::kOk;
  });
}
