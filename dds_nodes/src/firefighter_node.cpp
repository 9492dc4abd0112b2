#include "sarloc/dds/firefighter_node.hpp"

#include <spdlog/spdlog.h>

#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/validate.hpp"
#include "sarloc/dds/conversions.hpp"
#include "sarloc/dds/sign_off.hpp"
#include "sarloc/dds/speaker_claim.hpp"

namespace sarloc::dds {
namespace {
constexpr std::size_t kFixesQueued = 256;  // a stalled app loop drops the oldest
}  // namespace

void FirefighterNodeConfig::validate() const {
  if (responder_id.empty() || responder_id.size() > 64) {
    throw ConfigError("rescuers[].id = '" + responder_id + "': must be 1-64 characters");
  }
  if (team.empty() || team.size() > 64) throw ConfigError("rescuers[].team = '" + team + "': must be 1-64 characters");
  if (!(daemon_timeout_s > 0.0 && daemon_timeout_s <= 600.0)) {
    throw ConfigError("rescuer.fallback_timeout_s = " + config_value(daemon_timeout_s) + ": must be in (0, 600]");
  }
}

FirefighterNode::FirefighterNode(std::shared_ptr<Participant> participant, FirefighterNodeConfig config,
                                 MissionClock clock)
    : config_((config.validate(), std::move(config))),
      clock_(clock),
      participant_(std::move(participant)),
      // The others believe what this device says about its responder by its certificate's name.
      authority_((require_identity(*participant_, config_.responder_id, "rescuers[].id"), participant_)),
      odometry_writer_(participant_, EndpointOptions::in(config_.partitions)),
      alarm_writer_(participant_),
      position_writer_(participant_, device_position_options()) {
  position_reader_ = std::make_unique<Reader<::sarloc::ResponderPosition>>(
      participant_, [this](const ::sarloc::ResponderPosition& p, const auto& info) {
        if (p.responder_id().to_string() != config_.responder_id || participant_->is_own_writer(info.publication_handle)) {
          return;
        }
        try {
          auto fix = to_core(p);
          if (fix.source != responder::PositionSource::kMapAided) return;
          if (const SpeakerClaim claim = speaker_claim(p); !admits(authority_, info.publication_handle, claim)) {
            refusals_.warn(claim.responder_id, "unauthorized_writer",
                           refusal(authority_, info.publication_handle, claim));
            return;
          }
          std::lock_guard<std::mutex> lock(mutex_);
          // The daemon writes a silent firefighter's last position again (estimator::PositionRefresh):
          // a copy is neither a new fix nor a sign that the daemon hears this device.
          if (newest_fix_stamp_ != 0 && fix.stamp <= newest_fix_stamp_) return;
          newest_fix_stamp_ = fix.stamp;
          fixes_.push_back(std::move(fix));
          if (fixes_.size() > kFixesQueued) fixes_.pop_front();
          last_fix_at_ = clock_.now();
        } catch (const InputError& e) {
          spdlog::warn("ignoring a position from the daemon: {}", e.what());
        }
      });
}

FirefighterNode::~FirefighterNode() {
  position_reader_.reset();
  // The last alarms and positions reach incident command before the writers go.
  (void)alarm_writer_.wait_for_acknowledgments(std::chrono::milliseconds(500));
}

bool FirefighterNode::publish_odometry(const responder::Odometry& odometry) {
  position_writer_.assert_liveliness();  // the link is alive while the device steps, fix or not
  return odometry_writer_.write(to_idl(odometry));
}
bool FirefighterNode::publish_alarm(const responder::ResponderAlarm& alarm) { return alarm_writer_.write(to_idl(alarm)); }
bool FirefighterNode::publish_position(const responder::ResponderPosition& position) {
  return position_writer_.write(to_idl(position));
}

std::vector<responder::ResponderPosition> FirefighterNode::take_fixes() {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<responder::ResponderPosition> out(fixes_.begin(), fixes_.end());
  fixes_.clear();
  return out;
}

bool FirefighterNode::daemon_silent() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return last_fix_at_ == 0 || static_cast<double>(clock_.now() - last_fix_at_) > config_.daemon_timeout_s * 1e9;
}

bool FirefighterNode::wait_for_daemon(std::chrono::milliseconds timeout) const {
  return odometry_writer_.wait_for_readers(1, timeout);
}

bool FirefighterNode::sign_off(std::chrono::milliseconds timeout) {
  return dds::sign_off(position_writer_, config_.responder_id, timeout);
}

}  // namespace sarloc::dds
