// deploy/security/make-certs.sh produces material Fast DDS accepts: two secured nodes talk,
// an unauthenticated participant on the same domain hears nothing; only incident command's
// identities may publish the picture, and an identity from another CA injects nothing; a
// device's identity speaks only for its own responder.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "sarloc/dds/command_node.hpp"
#include "sarloc/dds/conversions.hpp"
#include "sarloc/dds/raw_topic_readers.hpp"
#include "sarloc/dds/raw_topic_type.hpp"
#include "sarloc/dds/reader.hpp"
#include "sarloc/dds/speaker_claim.hpp"
#include "sarloc/dds/topic_catalog.hpp"
#include "sarloc/dds/writer.hpp"
#include "sarloc/dds/writer_authority.hpp"
#include "support/dds_test_domains.hpp"
#include "support/dds_test_helpers.hpp"

namespace sarloc::dds {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

ParticipantConfig secure_config(const fs::path& dir, const std::string& node, std::uint32_t domain = test::kDomainSecurity) {
  ParticipantConfig c;
  c.profiles_file = (dir / node / "secure.xml").string();
  c.profile = "sarloc_secure";
  c.domain_id = domain;
  c.name = node;
  c.require_security = true;
  return c;
}

::sarloc::IncidentSummary summary(std::uint32_t n) {
  ::sarloc::IncidentSummary s;
  s.incident_id("secured");
  s.victims_total(n);
  return s;
}

TEST(Security, SecuredNodesTalkAndAnUnauthenticatedOneHearsNothing) {
  const fs::path dir = fs::temp_directory_path() / ("sarloc-security-test-" + std::to_string(getpid()));
  fs::remove_all(dir);
  const std::string make = std::string(SARLOC_SECURITY_DIR) + "/make-certs.sh " + dir.string() + " dashboard:alpha command:bravo > /dev/null";
  ASSERT_EQ(std::system(make.c_str()), 0) << make;

  // bravo publishes from another process: each process loads one node's secure.xml.
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    int code = 1;
    try {
      auto bravo = std::make_shared<Participant>(secure_config(dir, "bravo"));
      Writer<::sarloc::IncidentSummary> writer(bravo);
      if (bravo->secured() && writer.wait_for_readers(1, 20s)) {
        for (std::uint32_t i = 1; i <= 20; ++i) {
          writer.write(summary(i));
          std::this_thread::sleep_for(100ms);
        }
        code = 0;
      }
    } catch (...) {
    }
    _exit(code);
  }

  auto alpha = std::make_shared<Participant>(secure_config(dir, "alpha"));
  EXPECT_TRUE(alpha->secured());
  test::Inbox<::sarloc::IncidentSummary> secured_inbox;
  Reader<::sarloc::IncidentSummary> secured_reader(alpha, [&](const auto& s, const auto&) { secured_inbox.push(s); });
  auto outsider = test::make_participant(test::kDomainSecurity, "outsider");
  EXPECT_FALSE(outsider->secured());
  test::Inbox<::sarloc::IncidentSummary> outsider_inbox;
  Reader<::sarloc::IncidentSummary> outsider_reader(outsider, [&](const auto& s, const auto&) { outsider_inbox.push(s); });

  const auto got = secured_inbox.wait_for(3, 30s);
  int status = 0;
  waitpid(child, &status, 0);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "the secured writer never matched";
  EXPECT_GE(got.size(), 3U) << "secured nodes did not exchange data";
  EXPECT_TRUE(outsider_inbox.wait_for(1, 0ms).empty()) << "an unauthenticated participant received secured data";
  EXPECT_EQ(outsider_reader.matched_writers(), 0);
  fs::remove_all(dir);
}

/// In a child process (each loads one node's secure.xml, and Fast DDS keeps the first file of a
/// profile name for the process's life: ctest runs each test in a process of its own):
/// `node` publishes fused victim `id` for a few seconds. Exit 0 it published to a reader; 10 it
/// could not create the writer (its permissions forbid it); 20 it never matched a reader; 30 it
/// could not even create its participant.
pid_t publish_victim_in_child(const fs::path& dir, const std::string& node, std::uint32_t id) {
  const pid_t child = fork();
  if (child != 0) return child;
  int code = 30;
  try {
    auto participant = std::make_shared<Participant>(secure_config(dir, node, test::kDomainSecurityRoles));
    code = 20;
    std::unique_ptr<Writer<::sarloc::FusedVictim>> writer;
    try {
      writer = std::make_unique<Writer<::sarloc::FusedVictim>>(participant);
    } catch (const DdsError&) {
      _exit(10);
    }
    const bool matched = writer->wait_for_readers(1, 15s);
    ::sarloc::FusedVictim v;
    v.victim_id(id);
    v.state(::sarloc::VICTIM_FOUND);
    for (int k = 0; k < 20; ++k) {
      writer->write(v);
      std::this_thread::sleep_for(100ms);
    }
    code = matched ? 0 : 20;
  } catch (...) {
  }
  _exit(code);
}

// Issue 59, finding 3: a participant on the domain added a FOUND victim to the picture. With the
// shipped security material, a device's identity cannot even create a picture writer, and an
// identity named like incident command but issued by another CA matches nothing; incident
// command's own identity is heard.
TEST(Security, OnlyIncidentCommandPublishesThePictureAndAForgedIdentityInjectsNothing) {
  const fs::path dir = fs::temp_directory_path() / ("sarloc-security-roles-" + std::to_string(getpid()));
  const fs::path forged = dir / "forged";
  fs::remove_all(dir);
  const std::string script = std::string(SARLOC_SECURITY_DIR) + "/make-certs.sh ";
  ASSERT_EQ(std::system((script + dir.string() + " command:ic r1 dashboard:dash > /dev/null").c_str()), 0);
  ASSERT_EQ(std::system((script + forged.string() + " command:ic > /dev/null").c_str()), 0) << "an attacker's own CA";

  const pid_t command = publish_victim_in_child(dir, "ic", 1);
  const pid_t device = publish_victim_in_child(dir, "r1", 666);
  const pid_t impostor = publish_victim_in_child(forged, "ic", 667);
  ASSERT_GT(command, 0);
  ASSERT_GT(device, 0);
  ASSERT_GT(impostor, 0);

  // The dashboard's reader in a process of its own too: exit 0 it heard victim 1 and no other,
  // 1 it heard nothing, 2 it heard a victim from an identity that may not publish one.
  const pid_t dashboard = fork();
  ASSERT_GE(dashboard, 0);
  if (dashboard == 0) {
    int code = 1;
    try {
      auto participant = std::make_shared<Participant>(secure_config(dir, "dash", test::kDomainSecurityRoles));
      test::Inbox<std::uint32_t> ids;
      Reader<::sarloc::FusedVictim> reader(participant, [&](const auto& v, const auto&) { ids.push(v.victim_id()); });
      std::this_thread::sleep_for(20s);  // the publishers' whole lives
      const auto got = ids.wait_for(1, 0ms);
      if (!got.empty()) code = std::all_of(got.begin(), got.end(), [](std::uint32_t id) { return id == 1; }) ? 0 : 2;
    } catch (...) {
    }
    _exit(code);
  }
  int status = 0;
  waitpid(command, &status, 0);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "incident command's identity never matched the dashboard";
  waitpid(device, &status, 0);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 10) << "a device's identity created a picture writer (exit "
                                                               << WEXITSTATUS(status) << ")";
  waitpid(impostor, &status, 0);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 20) << "an identity of another CA matched (exit " << WEXITSTATUS(status) << ")";
  waitpid(dashboard, &status, 0);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0)
      << (WEXITSTATUS(status) == 2 ? "the dashboard heard a victim from an identity that may not publish one"
                                   : "the dashboard heard no victim from incident command");
  fs::remove_all(dir);
}

responder::ResponderPosition position_of(const std::string& id, const MissionClock& clock, double east, double north,
                                         responder::PositionSource source) {
  responder::ResponderPosition fix;
  fix.responder_id = id;
  fix.team_id = "north";
  fix.stamp = clock.now();
  fix.position.position = Vec3(east, north, 1.0);
  fix.position.covariance = 0.25 * Mat3::Identity();
  fix.source = source;
  return fix;
}

responder::ResponderAlarm mayday_of(const std::string& id, const MissionClock& clock) {
  responder::ResponderAlarm alarm;
  alarm.responder_id = id;
  alarm.team_id = "north";
  alarm.kind = responder::AlarmKind::kMayday;
  alarm.raised_at = clock.now();
  alarm.active = true;
  return alarm;
}

/// In a child process: `node` writes, after `delay`, for 4 s, what `write` writes once a
/// 200 ms, on responder_position and (a device's identity only: a core's may not) responder_alarm.
/// Exit 0 when its writers matched incident command, 20 when not, 30 on an error.
template <class WriteOnce>
pid_t speak_in_child(const fs::path& dir, const std::string& node, bool device, std::chrono::seconds delay,
                     WriteOnce write) {
  const pid_t child = fork();
  if (child != 0) return child;
  int code = 30;
  try {
    auto participant = std::make_shared<Participant>(secure_config(dir, node, test::kDomainSecurityIdentity));
    Writer<::sarloc::ResponderPosition> positions(participant);
    std::unique_ptr<Writer<::sarloc::ResponderAlarm>> alarms;
    if (device) alarms = std::make_unique<Writer<::sarloc::ResponderAlarm>>(participant);
    code = positions.wait_for_readers(1, 20s) && (!alarms || alarms->wait_for_readers(1, 20s)) ? 0 : 20;
    std::this_thread::sleep_for(delay);
    for (int k = 0; k < 20; ++k) {
      write(positions, alarms.get());
      std::this_thread::sleep_for(200ms);
    }
    std::this_thread::sleep_for(1s);  // reliable delivery of the last ones
  } catch (...) {
  }
  _exit(code);
}

// The dashboard's Foxglove feed relays raw payloads (RawSampleAuthority), in a process of its own
// with the dashboard's identity, for up to 30 s. Exit bits: 1 a mayday for r1 relayed (r2 wrote
// it), 2 r2's own mayday never relayed, 4 a fix of r1 that r2 wrote relayed, 8 the core daemon's
// fix of r1 never relayed, 16 r2's own fix never relayed; 64 an error.
pid_t relay_feed_in_child(const fs::path& dir) {
  const pid_t child = fork();
  if (child != 0) return child;
  int code = 64;
  try {
    auto config = secure_config(dir, "dash", test::kDomainSecurityIdentity);
    config.core_node_ids = {"core-a"};
    auto participant = std::make_shared<Participant>(config);
    const RawSampleAuthority authority(participant);
    const std::vector<const CatalogTopic*> topics = {find_catalog_topic("sarloc/responder_alarm"),
                                                     find_catalog_topic("sarloc/responder_position")};
    std::atomic<int> r1_mayday{0}, r2_mayday{0}, r1_spoofed{0}, r1_core{0}, r2_fix{0};
    RawReaderEvents events;
    events.on_sample = [&](std::size_t k, RawSample&& sample, const eprosima::fastdds::dds::SampleInfo& info) {
      if (!authority.refusal(topics[k]->name, sample.bytes, info.publication_handle).empty()) return;
      if (k == 0) {
        ::sarloc::ResponderAlarm a;
        if (decode_payload<::sarloc::ResponderAlarmPubSubType>(sample.bytes, a))
          ++(a.responder_id() == "r1" ? r1_mayday : r2_mayday);
        return;
      }
      ::sarloc::ResponderPosition p;
      if (!decode_payload<::sarloc::ResponderPositionPubSubType>(sample.bytes, p)) return;
      const responder::ResponderPosition fix = to_core(p);
      if (fix.responder_id == "r2") ++r2_fix;
      if (fix.responder_id == "r1") ++(std::abs(fix.position.position.x() - 5.0) < 1e-6 ? r1_core : r1_spoofed);
    };
    RawTopicReaders readers(participant, topics, {"*"}, events);
    // r2 writes its own fix last in each round: five of them, and its spoofs were all seen.
    for (int waited = 0; waited < 300 && r2_fix < 5; ++waited) std::this_thread::sleep_for(100ms);
    std::this_thread::sleep_for(500ms);
    readers.close();
    code = (r1_mayday > 0 ? 1 : 0) | (r2_mayday == 0 ? 2 : 0) | (r1_spoofed > 0 ? 4 : 0) | (r1_core == 0 ? 8 : 0) |
           (r2_fix == 0 ? 16 : 0);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "the feed's process: %s\n", e.what());
  }
  _exit(code);
}

// Issue 59: DDS Security grants topics, not instances, so every device identity may publish
// responder_position and responder_alarm. Incident command now checks each sample's writer
// against the responder it is about (WriterAuthority): device r2 can raise neither a mayday
// "for r1" nor move r1 on the map, by a GNSS or a forged map-aided fix; r2's own alarm and
// position, and the core daemon's map-aided fix of r1, still count.
TEST(Security, ADeviceSpeaksOnlyForItsOwnResponder) {
  const fs::path dir = fs::temp_directory_path() / ("sarloc-security-identity-" + std::to_string(getpid()));
  fs::remove_all(dir);
  const std::string make = std::string(SARLOC_SECURITY_DIR) + "/make-certs.sh " + dir.string() +
                           " command:ic core:core-a dashboard:dash r2 > /dev/null";
  ASSERT_EQ(std::system(make.c_str()), 0) << make;
  const MissionClock clock;  // one epoch for every process: the children inherit it
  const pid_t feed = relay_feed_in_child(dir);
  ASSERT_GT(feed, 0);

  // The core daemon places r1 first; device r2 speaks (for itself and for r1) once it is done,
  // so a spoof that got through would be r1's last position.
  const pid_t core = speak_in_child(dir, "core-a", false, 0s, [&](auto& positions, auto*) {
    positions.write(to_idl(position_of("r1", clock, 5.0, 5.0, responder::PositionSource::kMapAided)));
  });
  const pid_t device = speak_in_child(dir, "r2", true, 6s, [&](auto& positions, auto* alarms) {
    alarms->write(to_idl(mayday_of("r1", clock)));
    alarms->write(to_idl(mayday_of("r2", clock)));
    positions.write(to_idl(position_of("r1", clock, 400.0, -400.0, responder::PositionSource::kGnss)));
    positions.write(to_idl(position_of("r1", clock, -400.0, 400.0, responder::PositionSource::kMapAided)));
    positions.write(to_idl(position_of("r2", clock, 1.0, 1.0, responder::PositionSource::kGnss)));
  });
  ASSERT_GT(core, 0);
  ASSERT_GT(device, 0);

  auto config = secure_config(dir, "ic", test::kDomainSecurityIdentity);
  config.core_node_ids = {"core-a"};
  auto participant = std::make_shared<Participant>(config);
  // The identity a reader derives from a name is the one Fast DDS's authentication gave.
  EXPECT_TRUE(proves_identity(*participant, "ic"));
  EXPECT_FALSE(proves_identity(*participant, "r2"));
  CommandNodeConfig command_config;
  command_config.node_id = "ic";
  command_config.incident.incident_id = "identity-test";
  command_config.cycle_s = 0.1;
  CommandNode command(participant, command_config, clock);

  int status = 0;
  waitpid(core, &status, 0);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "the core daemon's identity never matched";
  waitpid(device, &status, 0);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "device r2 never matched";
  std::this_thread::sleep_for(500ms);  // a cycle or two

  bool r2_mayday = false;
  for (const auto& alarm : command.alarms()) {
    EXPECT_NE(alarm.alarm.responder_id, "r1") << "a mayday for r1 from r2's identity reached the alarm board";
    r2_mayday = r2_mayday || (alarm.alarm.responder_id == "r2" && alarm.alarm.kind == responder::AlarmKind::kMayday);
  }
  EXPECT_TRUE(r2_mayday) << "r2's own mayday was lost";
  std::map<std::string, incident::MemberStatus> members;
  for (const auto& team : command.teams()) {
    for (const auto& member : team.members) members[member.responder_id] = member;
  }
  ASSERT_EQ(members.count("r1"), 1U) << "the core daemon's fix of r1 was lost";
  EXPECT_NEAR(members["r1"].last_position.position.x(), 5.0, 1e-6) << "r2 moved r1 on the map";
  EXPECT_NEAR(members["r1"].last_position.position.y(), 5.0, 1e-6);
  ASSERT_EQ(members.count("r2"), 1U) << "r2's own position was lost";
  EXPECT_NEAR(members["r2"].last_position.position.x(), 1.0, 1e-6);
  waitpid(feed, &status, 0);
  ASSERT_TRUE(WIFEXITED(status)) << "the feed's process died";
  const int feed_code = WEXITSTATUS(status);
  EXPECT_NE(feed_code, 64) << "the feed's process failed to run";
  EXPECT_EQ(feed_code & 1, 0) << "the Foxglove feed relayed r2's mayday for r1";
  EXPECT_EQ(feed_code & 2, 0) << "the Foxglove feed lost r2's own mayday";
  EXPECT_EQ(feed_code & 4, 0) << "the Foxglove feed relayed r2's fixes of r1";
  EXPECT_EQ(feed_code & 8, 0) << "the Foxglove feed lost the core daemon's fix of r1";
  EXPECT_EQ(feed_code & 16, 0) << "the Foxglove feed lost r2's own fix";
  fs::remove_all(dir);
}

}  // namespace
}  // namespace sarloc::dds
