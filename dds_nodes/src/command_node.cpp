#include "sarloc/dds/command_node.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>

#include "sarloc/core/incident/source_estimate.hpp"
#include "sarloc/dds/conversions.hpp"
#include "sarloc/dds/process_stats.hpp"

namespace sarloc::dds {

void CommandNodeConfig::validate() const {
  fusion.validate();
  teams.validate();
  if (node_id.empty() || node_id.size() > 64) throw ConfigError("command.node_id = '" + node_id + "': must be 1-64 characters");
  if (incident_id.empty() || incident_id.size() > 64) {
    throw ConfigError("incident.id = '" + incident_id + "': must be 1-64 characters");
  }
  if (!(cycle_s > 0.0 && cycle_s <= 60.0)) throw ConfigError("command.cycle_s = " + std::to_string(cycle_s) + ": must be in (0, 60]");
  if (!(position_max_age_s > 0.0 && position_max_age_s <= 600.0)) {
    throw ConfigError("command.position_max_age_s = " + std::to_string(position_max_age_s) + ": must be in (0, 600]");
  }
  if (!(fix_interpolation_max_gap_s >= 0.0 && fix_interpolation_max_gap_s <= 60.0)) {
    throw ConfigError("command.fix_interpolation_max_gap_s = " + std::to_string(fix_interpolation_max_gap_s) +
                      ": must be in [0, 60]");
  }
  if (!(fix_wait_s > 0.0 && fix_wait_s <= 600.0)) {
    throw ConfigError("command.fix_wait_s = " + std::to_string(fix_wait_s) + ": must be in (0, 600]");
  }
  if (!(antenna_height_m >= 0.0 && antenna_height_m <= 5.0)) {
    throw ConfigError("command.antenna_height_m = " + std::to_string(antenna_height_m) + ": must be in [0, 5]");
  }
  if (!(antenna_height_sigma_m > 0.0 && antenna_height_sigma_m <= 5.0)) {
    throw ConfigError("command.antenna_height_sigma_m = " + std::to_string(antenna_height_sigma_m) + ": must be in (0, 5]");
  }
  if (!(origin.latitude_deg >= -90.0 && origin.latitude_deg <= 90.0)) {
    throw ConfigError("incident.latitude_deg = " + std::to_string(origin.latitude_deg) + ": must be in [-90, 90]");
  }
  if (!(origin.longitude_deg >= -180.0 && origin.longitude_deg <= 180.0)) {
    throw ConfigError("incident.longitude_deg = " + std::to_string(origin.longitude_deg) + ": must be in [-180, 180]");
  }
}

CommandNode::CommandNode(std::shared_ptr<Participant> participant, CommandNodeConfig config, MissionClock clock)
    : config_((config.validate(), std::move(config))),
      clock_(clock),
      participant_(std::move(participant)),
      warnings_(std::chrono::seconds(5)),
      fusion_(config_.fusion),
      tracker_(config_.teams),
      victim_writer_(participant_),
      team_writer_(participant_),
      summary_writer_(participant_),
      frame_writer_(participant_),
      status_writer_(participant_) {
  ::sarloc::IncidentFrame frame;
  frame.incident_id(config_.incident_id);
  frame.latitude_deg(config_.origin.latitude_deg);
  frame.longitude_deg(config_.origin.longitude_deg);
  frame.altitude_m(config_.origin.altitude_m);
  frame.name(config_.incident_name.substr(0, ::sarloc::TEXT_MAX));
  frame.established(clock_.now());
  frame_writer_.write(frame);

  estimate_reader_ = std::make_unique<Reader<::sarloc::VictimEstimate>>(
      participant_,
      [this](const ::sarloc::VictimEstimate& e, const auto& info) {
        try {
          auto estimate = to_core(e);
          // The writer tells the daemon's estimates from a device's own: two estimators of one
          // source, which VictimFusion holds to agreeing with each other.
          std::string writer;
          for (int i = 0; i < 16; ++i) writer += fmt::format("{:02x}", info.publication_handle.value[i]);
          spdlog::debug("estimate {}/{} status {} stamp {} from writer {} relative ({:.2f}, {:.2f}, {:.2f})",
                        estimate.rescuer_id, estimate.signal_id, static_cast<int>(estimate.status), estimate.stamp,
                        writer, estimate.relative.position.x(), estimate.relative.position.y(),
                        estimate.relative.position.z());
          std::lock_guard<std::mutex> lock(mutex_);
          pending_estimates_.push_back({std::move(estimate), std::move(writer), e.from_device()});
        } catch (const InputError& error) {
          counters_.rejected("invalid_value");
          warnings_.warn(e.rescuer_id().to_string(), "invalid_value", std::string("victim estimate: ") + error.what());
        }
      },
      EndpointOptions::in(config_.estimate_partitions));

  ReaderEvents events;
  events.on_liveliness = [this](const auto& handle, bool alive) {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& [writer, responder] : writer_owner_) {
      if (writer == handle) {
        tracker_.on_link(responder, alive, clock_.now());
        if (!alive) spdlog::warn("{}: link to responder '{}' lost", config_.node_id, responder);
      }
    }
  };
  position_reader_ = std::make_unique<Reader<::sarloc::ResponderPosition>>(
      participant_,
      [this](const ::sarloc::ResponderPosition& p, const auto& info) {
        try {
          auto position = to_core(p);
          if (!position.position.position.allFinite() || !position.position.covariance.allFinite()) {
            throw InputError("responder_position.position: non-finite value");
          }
          std::lock_guard<std::mutex> lock(mutex_);
          auto& owners = writer_owner_;
          const bool known = std::any_of(owners.begin(), owners.end(),
                                         [&](const auto& o) { return o.first == info.publication_handle; });
          if (!known) owners.emplace_back(info.publication_handle, position.responder_id);
          tracker_.on_position(position, clock_.now());
          // GNSS heights become the antenna's above the snow; indoor positions keep theirs.
          fixes_[position.responder_id].add(
              position.stamp, incident::reporter_fix_of(position, config_.antenna_height_m, config_.antenna_height_sigma_m));
        } catch (const InputError& error) {
          counters_.rejected("invalid_value");
          warnings_.warn(p.responder_id().to_string(), "invalid_value", error.what());
        }
      },
      EndpointOptions{}, events);

  thread_ = std::thread([this] {
    while (!stopping_.load()) {
      cycle();
      const auto until =
          std::chrono::steady_clock::now() + std::chrono::milliseconds(static_cast<std::int64_t>(config_.cycle_s * 1000));
      while (!stopping_.load() && std::chrono::steady_clock::now() < until) {
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
      }
    }
  });
}

CommandNode::~CommandNode() {
  estimate_reader_.reset();
  position_reader_.reset();
  stopping_.store(true);
  thread_.join();
}

std::optional<incident::ReporterFix> CommandNode::fix_at(const std::string& rescuer_id, TimestampNs stamp) const {
  const auto it = fixes_.find(rescuer_id);
  if (it == fixes_.end()) return std::nullopt;
  return it->second.at(stamp, static_cast<TimestampNs>(config_.position_max_age_s * 1e9),
                       static_cast<TimestampNs>(config_.fix_interpolation_max_gap_s * 1e9));
}

void CommandNode::cycle() {
  static thread_local ProcessStats stats;
  std::vector<incident::FusedVictim> victims;
  std::vector<std::uint32_t> removed;
  std::vector<incident::TeamStatus> teams;
  const TimestampNs now = clock_.now();
  std::size_t responders = 0;
  std::size_t lost = 0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    std::deque<PendingEstimate> waiting;
    while (!pending_estimates_.empty()) {
      auto pending = std::move(pending_estimates_.front());
      pending_estimates_.pop_front();
      const auto& e = pending.estimate;
      if (e.status < responder::EstimatorStatus::kConverged) continue;  // a multimodal mean means nothing
      const auto fix = fix_at(e.rescuer_id, e.stamp);
      if (!fix) {
        spdlog::debug("no fix of '{}' near stamp {}: estimate waits", e.rescuer_id, e.stamp);
        // The fix may still be on its way: keep the estimate for the next cycle, briefly.
        if (static_cast<double>(now - e.stamp) < config_.fix_wait_s * 1e9) waiting.push_back(std::move(pending));
        continue;
      }
      try {
        auto source = incident::make_source_estimate(e, *fix);
        source.estimator = pending.writer;
        source.from_device = pending.from_device;
        spdlog::trace("source {}/{} stamp {} status {} at ({:.2f}, {:.2f}, {:.2f}) sd ({:.2f}, {:.2f}, {:.2f})",
                      source.rescuer_id, source.signal_id, source.stamp, static_cast<int>(source.state),
                      source.position.position.x(), source.position.position.y(), source.position.position.z(),
                      std::sqrt(source.position.covariance(0, 0)), std::sqrt(source.position.covariance(1, 1)),
                      std::sqrt(source.position.covariance(2, 2)));
        fusion_.update(source);
        counters_.accepted();
      } catch (const InputError& error) {
        counters_.rejected("invalid_value");
        warnings_.warn(e.rescuer_id, "invalid_value", error.what());
      }
    }
    pending_estimates_ = std::move(waiting);
    fusion_.step(now);
    victims = fusion_.victims();
    if (spdlog::should_log(spdlog::level::trace)) {
      for (const auto& v : victims) {
        std::string sources;
        for (const auto& src : v.sources) sources += " " + src.rescuer_id + "/" + std::to_string(src.signal_id);
        spdlog::trace("victim {} state {} at ({:.2f}, {:.2f}, {:.2f}) sources{}", v.victim_id, static_cast<int>(v.state),
                      v.position.position.x(), v.position.position.y(), v.position.position.z(), sources);
      }
    }
    removed = fusion_.take_removed();
    teams = tracker_.evaluate(now);
    last_teams_ = teams;
    responders = tracker_.responders_total();
    lost = tracker_.link_lost_count(now);
  }

  for (const auto id : removed) {
    ::sarloc::FusedVictim key;
    key.victim_id(id);
    victim_writer_.dispose(key);
  }
  std::uint32_t located = 0;
  std::uint32_t found = 0;
  for (const auto& v : victims) {
    if (v.state != incident::VictimState::kUnconfirmed) ++located;
    if (incident::is_found(v.state)) ++found;
    try {
      victim_writer_.write(to_idl(v));
    } catch (const InputError& e) {
      spdlog::error("cannot publish victim {}: {}", v.victim_id, e.what());
    }
  }
  for (const auto& t : teams) {
    try {
      team_writer_.write(to_idl(t));
    } catch (const InputError& e) {
      spdlog::error("cannot publish team '{}': {}", t.team_id, e.what());
    }
  }
  ::sarloc::IncidentSummary summary;
  summary.incident_id(config_.incident_id);
  summary.stamp(now);
  summary.victims_total(static_cast<std::uint32_t>(victims.size()));
  summary.victims_located(located);
  summary.victims_found(found);
  summary.responders_total(static_cast<std::uint32_t>(responders));
  summary.responders_link_lost(static_cast<std::uint32_t>(lost));
  summary_writer_.write(summary);

  const auto snapshot = counters_.snapshot();
  ::sarloc::NodeStatus status;
  status.node_id(config_.node_id);
  status.kind(::sarloc::NODE_COMMAND);
  status.stamp(now);
  status.samples_accepted(snapshot.accepted);
  status.samples_rejected(snapshot.rejected);
  status.cpu_percent(stats.cpu_percent());
  status.rss_mb(ProcessStats::rss_mb());
  status_writer_.write(status);
}

std::vector<incident::FusedVictim> CommandNode::victims() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return fusion_.victims();
}

std::vector<incident::TeamStatus> CommandNode::teams() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return last_teams_;
}

}  // namespace sarloc::dds
