// sarloc-dashboard: the incident commander's screen, a web page served by this process on the
// incident picture over DDS (docs/operations/dashboard.md). Binds 127.0.0.1 unless told
// otherwise; every operator action needs the access token.
//
// Exit codes: 0 stopped by SIGINT/SIGTERM; 2 bad command line; 3 bad mission file or options;
// 4 could not run (DDS, the address in use).
#include <fcntl.h>
#include <malloc.h>
#include <spdlog/spdlog.h>
#include <sys/stat.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>

#include "dashboard_server.hpp"
#include "foxglove_bridge.hpp"
#include "picture_state.hpp"
#include "recording_player.hpp"
#include "sarloc/app/command_line.hpp"
#include "sarloc/app/logging.hpp"
#include "sarloc/app/node_options.hpp"
#include "sarloc/app/run_main.hpp"
#include "sarloc/app/shutdown_signal.hpp"
#include "sarloc/dds/dashboard_node.hpp"
#include "sarloc/dds/idl_schemas.hpp"
#include "sarloc/dds/rate_limited_log.hpp"
#include "sarloc/dds/raw_topic_readers.hpp"
#include "sarloc/dds/speaker_claim.hpp"
#include "sarloc/dds/topic_catalog.hpp"

int main(int argc, char** argv) {
  using namespace sarloc;
  // Few malloc arenas: every event stream has a thread of its own, and per-thread arenas would
  // keep each stream's largest snapshot (docs/operations/dashboard.md, memory).
  ::mallopt(M_ARENA_MAX, 2);
  app::install_shutdown_handlers();
  CLI::App cli{"sarloc-dashboard: the incident-command web page on the incident picture"};
  app::NodeOptions options;
  app::add_node_options(cli, options);
  std::string bind, token, view_token, url_file, recording;
  int port = -1;
  int foxglove_port = -2;
  cli.add_option("--bind", bind, "address to listen on, overriding dashboard.bind_address (default 127.0.0.1)");
  cli.add_option("--port", port, "port, overriding dashboard.port (0: any free port)");
  cli.add_option("--token", token, "access token for operator actions (also SARLOC_DASHBOARD_TOKEN; default: random)");
  cli.add_option("--view-token", view_token, "access token for looking only (also SARLOC_DASHBOARD_VIEW_TOKEN; default: random)");
  cli.add_option("--url-file", url_file,
                 "once serving, write three lines to this file (mode 0600): the operator's URL, the Foxglove feed's, a viewer's URL");
  cli.add_option("--foxglove-port", foxglove_port, "the Foxglove WebSocket feed's port, overriding dashboard.foxglove_port (-1: off)");
  cli.add_option("--recording", recording, "show this recording (.mcap) instead of live DDS, with a timeline to play, pause and scrub");
  if (auto code = app::parse_command_line(cli, argc, argv)) return *code;

  return app::run_main("sarloc-dashboard", [&] {
    app::setup_logging(options.log_level, "dashboard");
    const auto mission = app::load_mission_config(options.config_path);
    app::DashboardConfig settings = mission.dashboard;
    if (!bind.empty()) settings.bind_address = bind;
    if (port >= 0) settings.port = port;
    if (foxglove_port >= -1) settings.foxglove_port = foxglove_port;
    if (token.empty() && std::getenv("SARLOC_DASHBOARD_TOKEN") != nullptr) token = std::getenv("SARLOC_DASHBOARD_TOKEN");
    if (!token.empty()) settings.token = token;
    const bool generated = settings.token.empty();
    if (generated) settings.token = dashboard::random_secret();
    if (view_token.empty() && std::getenv("SARLOC_DASHBOARD_VIEW_TOKEN") != nullptr) view_token = std::getenv("SARLOC_DASHBOARD_VIEW_TOKEN");
    if (!view_token.empty()) settings.view_token = view_token;
    if (settings.view_token.empty()) settings.view_token = dashboard::random_secret();
    settings.validate();

    const auto clock = options.clock(mission);
    dashboard::PictureStateConfig state_config;
    state_config.track_length = static_cast<std::size_t>(settings.track_length);
    state_config.par_interval_s = settings.par_interval_s;
    state_config.stale_after_s = settings.stale_after_s;
    // Where the picture sits: its WGS-84 origin, the avalanche deposit and the building placed in it.
    std::shared_ptr<const app::Basemap> basemap;
    if (!settings.basemap.empty())
      basemap = std::make_shared<const app::Basemap>(settings.basemap, "dashboard.basemap");
    auto place = [&](dashboard::PictureState& state) {
      state.set_geodetic_origin(mission.command.incident.origin);
      if (mission.deposit) state.set_deposit(mission.deposit->vertices());
      if (basemap) {
        const auto tiles =
            app::tiles_over_incident(*basemap, incident::GeodeticFrame(mission.command.incident.origin),
                                     mission.deposit ? mission.deposit->vertices() : std::vector<Eigen::Vector2d>{});
        state.set_extra("basemap", app::basemap_json(tiles));
        spdlog::info("basemap {}: {} tiles at zoom {} over the incident", settings.basemap, tiles.size(),
                     tiles.empty() ? 0 : tiles.front().zoom);
        if (tiles.empty()) spdlog::warn("basemap {}: no tile over the incident (another place?)", settings.basemap);
      }
      if (!mission.world) return;
      const auto& f = mission.estimators.firefighter;
      state.set_building({*mission.world, f.origin.x(), f.origin.y(), f.rotation_rad()});
    };
    dashboard::DashboardServerConfig server_config;
    server_config.bind_address = settings.bind_address;
    server_config.port = settings.port;
    server_config.token = settings.token;
    server_config.view_token = settings.view_token;
    server_config.operator_id = settings.operator_id;
    server_config.push_period_s = settings.push_period_s;
    server_config.max_streams = settings.max_streams;
    server_config.max_connections_per_address = settings.max_connections_per_address;
    server_config.request_deadline_s = settings.request_deadline_s;
    server_config.tls_certificate = settings.tls_certificate;
    server_config.tls_private_key = settings.tls_private_key;
    server_config.tls_client_ca = settings.tls_client_ca;
    server_config.hosts = settings.hosts;

    auto announce = [&](int port_in_use, int foxglove_in_use) {
      const std::string host = settings.bind_address == "0.0.0.0" ? "127.0.0.1" : settings.bind_address;
      const std::string page = std::string(settings.tls_certificate.empty() ? "http" : "https") + "://" + host + ":" +
                               std::to_string(port_in_use) + "/";
      const std::string url = page + "#token=" + settings.token;
      // The token goes to whoever started the dashboard, never into its log.
      spdlog::info("dashboard of mission '{}' at {}; the operator token is {}{}", mission.name, page,
                   url_file.empty() ? "in the URL printed on standard output" : "in " + url_file + " (mode 0600)",
                   generated ? " (a random one: give it to operators)" : "");
      if (url_file.empty()) {
        std::printf("%s\n", url.c_str());
        std::fflush(stdout);
      }
      if (settings.bind_address != "127.0.0.1" && settings.bind_address != "localhost") {
        spdlog::warn("listening on {}: anyone on that network sees the picture; actions need the token", settings.bind_address);
      }
      // Foxglove and Lichtblick take the URL as it is: the view token rides in its query.
      const std::string feed = foxglove_in_use > 0 ? std::string(settings.tls_certificate.empty() ? "ws" : "wss") + "://" + host + ":" + std::to_string(foxglove_in_use) + "/?token=" + settings.view_token : "";
      const std::string viewer = page + "#token=" + settings.view_token;
      if (foxglove_in_use > 0) spdlog::info("Foxglove WebSocket feed (foxglove.websocket.v1) on port {} (the view token in its URL's query)", foxglove_in_use);
      if (!url_file.empty()) {
        // Whole or not at all: whoever waits for the file reads both lines.
        // Readable by its owner only: it holds the token.
        const std::string text = url + "\n" + feed + "\n" + viewer + "\n";
        const int fd = ::open((url_file + ".tmp").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
        const bool written = fd >= 0 && ::fchmod(fd, 0600) == 0 && ::write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size());
        if (fd >= 0) ::close(fd);
        if (!written || std::rename((url_file + ".tmp").c_str(), url_file.c_str()) != 0) {
          spdlog::error("could not write {}: {}", url_file, std::strerror(errno));
        }
      }
    };

    if (!recording.empty()) {
      // The debrief view: a recording instead of DDS, on the recording's own clocks.
      dashboard::RecordingPlayer player(recording);
      if (!player.damage().empty()) spdlog::warn("the recording is damaged: {}; showing what could be read", player.damage());
      dashboard::PictureState state(state_config, [&player] { return player.mission_now(); }, player.epoch_ns(),
                                    [&player] { return player.wall_now_s(); });
      place(state);
      state.set_extra("dds_security", "recording");
      state.set_extra("incident", {{"id", mission.command.incident.incident_id}, {"name", mission.command.incident.incident_name}});
      player.attach(state);
      player.seek(0.0);
      dashboard::DashboardServer server(server_config, state, [](std::uint32_t, const std::string&) { return false; });
      server.set_basemap(basemap);
      server.set_replay_control([&player](const nlohmann::json& request) { return player.control(request); });
      server.start();
      spdlog::info("replaying '{}': {} picture samples", recording, player.samples());
      announce(server.port(), -1);
      while (!app::wait_for_shutdown(std::chrono::milliseconds(100))) player.tick();
      server.stop();
      return app::ExitCode::kOk;
    }

    dashboard::PictureState state(state_config, [clock] { return clock.now(); }, clock.epoch());
    place(state);
    auto participant = std::make_shared<sarloc::dds::Participant>(
        options.participant(mission, "sarloc-dashboard", app::kDashboardIdentity));
    // Shown on the page's header: in red when anyone on the network could have written the picture.
    state.set_extra("dds_security", participant->secured() ? "authenticated, encrypted" : "none");
    state.set_extra("incident", {{"id", mission.command.incident.incident_id}, {"name", mission.command.incident.incident_name}});
    if (!participant->secured()) spdlog::warn("DDS Security is off: the page says so in red (docs/operations.md, \"Security\")");
    sarloc::dds::DashboardSink sink;
    sink.on_victim = [&](const auto& v) { state.on_victim(v); };
    sink.on_victim_gone = [&](auto id) { state.on_victim_gone(id); };
    sink.on_team = [&](const auto& t) { state.on_team(t); };
    sink.on_alarm = [&](const auto& a) { state.on_alarm(a); };
    sink.on_alarm_gone = [&](auto id) { state.on_alarm_gone(id); };
    sink.on_position = [&](const auto& p) { state.on_position(p); };
    sink.on_candidates = [&](const auto& c) { state.on_candidates(c); };
    sink.on_guidance = [&](const auto& g) { state.on_guidance(g); };
    sink.on_search_plan = [&](const auto& plan) { state.on_search_plan(plan); };
    sink.on_picture_writer = [&](const auto& w) { state.on_picture_writer(w); };
    sink.on_rejected = [&](const auto& topic) { state.on_rejected(topic); };
    sarloc::dds::DashboardNode node(participant, sink);

    dashboard::DashboardServer server(server_config, state, [&](std::uint32_t id, const std::string& op) {
      return node.acknowledge(id, op, clock.now());
    });
    server.set_dug_out_action(
        [&](std::uint32_t id, const std::string& op) { return node.report_dug_out(id, op, clock.now()); });
    server.set_basemap(basemap);
    server.set_deposit_action([&](const std::vector<Eigen::Vector2d>& outline, const std::string& op) {
      return node.draw_deposit(mission.command.incident.incident_id, outline, op, clock.now());
    });
    server.set_dig_order_action([&](const std::vector<std::uint32_t>& ids, const std::string& op) {
      return node.set_dig_order(mission.command.incident.incident_id, ids, op, clock.now());
    });
    server.start();

    // The Foxglove feed: every topic's payloads as they arrive, on a participant of its own
    // (raw readers cannot share topics with the typed ones above).
    std::unique_ptr<dashboard::FoxgloveBridge> foxglove;
    std::shared_ptr<sarloc::dds::Participant> raw_participant;
    std::unique_ptr<sarloc::dds::RawTopicReaders> raw_readers;
    if (settings.foxglove_port >= 0) {
      std::vector<dashboard::FoxgloveChannel> channels;
      std::vector<const sarloc::dds::CatalogTopic*> topics;
      for (const auto& topic : sarloc::dds::topic_catalog()) {
        channels.push_back({static_cast<std::uint32_t>(channels.size() + 1), topic.name, topic.type_name,
                            sarloc::dds::self_contained_idl(topic.idl_file)});
        topics.push_back(&topic);
      }
      dashboard::FoxgloveBridgeConfig feed;
      feed.bind_address = settings.bind_address;
      feed.port = settings.foxglove_port;
      feed.allowed_origins = settings.feed_origins;
      feed.access = server.sessions();
      // Beyond loopback the page has TLS, and so does the feed, with the same client authority.
      feed.tls = {settings.tls_certificate, settings.tls_private_key, settings.tls_client_ca};
      foxglove = std::make_unique<dashboard::FoxgloveBridge>(feed, channels);
      foxglove->start();
      raw_participant = std::make_shared<sarloc::dds::Participant>(
          options.participant(mission, "sarloc-dashboard-foxglove", app::kDashboardIdentity));
      sarloc::dds::RawReaderEvents events;
      // A sample about a responder is relayed only from a writer that may speak for it, as the
      // picture is built (under DDS Security a stolen device's mayday "for r1" reached the feed).
      std::vector<std::string> topic_names;
      for (const auto* topic : topics) topic_names.push_back(topic->name);
      auto feed_authority = std::make_shared<sarloc::dds::RawSampleAuthority>(raw_participant);
      auto feed_refusals = std::make_shared<sarloc::dds::RateLimitedLog>(std::chrono::seconds(10));
      events.on_sample = [&foxglove, &state, topic_names, feed_authority, feed_refusals](
                             std::size_t k, sarloc::dds::RawSample&& sample,
                             const eprosima::fastdds::dds::SampleInfo& info) {
        if (const std::string why = feed_authority->refusal(topic_names[k], sample.bytes, info.publication_handle);
            !why.empty()) {
          state.on_rejected("feed " + topic_names[k]);
          feed_refusals->warn(topic_names[k], "feed_refused", "Foxglove feed: not relayed: " + why);
          return;
        }
        const std::int64_t stamp = info.source_timestamp.to_ns();
        foxglove->publish(static_cast<std::uint32_t>(k + 1), stamp > 0 ? static_cast<std::uint64_t>(stamp) : 0, sample.bytes.data(),
                          sample.bytes.size());
      };
      raw_readers = std::make_unique<sarloc::dds::RawTopicReaders>(raw_participant, topics, std::vector<std::string>{"*"}, events);
    }
    announce(server.port(), foxglove ? foxglove->port() : -1);
    while (!app::wait_for_shutdown(std::chrono::seconds(1))) {
    }
    spdlog::info("dashboard stopping");
    if (raw_readers) raw_readers->close();
    if (foxglove) foxglove->stop();
    server.stop();
    return app::ExitCode::kOk;
  });
}
