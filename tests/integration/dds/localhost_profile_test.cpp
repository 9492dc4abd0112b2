// The localhost profile is really applied: the participant's transports are the profile's,
// and what it announces to a peer through discovery is only loopback or shared memory.
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/domain/DomainParticipantListener.hpp>
#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastdds/rtps/transport/shared_mem/SharedMemTransportDescriptor.h>
#include <fastrtps/utils/IPLocator.h>
#include <gtest/gtest.h>

#include <condition_variable>

#include "sarloc/dds/dds_error.hpp"
#include "sarloc/dds/reader.hpp"
#include "sarloc/dds/writer.hpp"
#include "support/dds_test_domains.hpp"
#include "support/dds_test_helpers.hpp"

namespace sarloc::dds {
namespace {

using eprosima::fastdds::rtps::SharedMemTransportDescriptor;
using eprosima::fastdds::rtps::UDPv4TransportDescriptor;
using eprosima::fastrtps::rtps::IPLocator;
using eprosima::fastrtps::rtps::Locator_t;

TEST(LocalhostProfile, ParticipantUsesOnlyTheProfilesLoopbackAndShmTransports) {
  auto participant = test::make_participant(test::kDomainLocalhostProfile, "profile-check");
  const auto& qos = participant->get()->get_qos();
  EXPECT_EQ(qos.name().to_string(), "profile-check");
  EXPECT_FALSE(qos.transport().use_builtin_transports) << "builtin transports would add every interface";
  ASSERT_EQ(qos.transport().user_transports.size(), 2U);
  int udp = 0;
  int shm = 0;
  for (const auto& descriptor : qos.transport().user_transports) {
    if (auto* u = dynamic_cast<UDPv4TransportDescriptor*>(descriptor.get())) {
      ++udp;
      ASSERT_EQ(u->interfaceWhiteList.size(), 1U);
      EXPECT_EQ(u->interfaceWhiteList.front(), "127.0.0.1");
    } else if (dynamic_cast<SharedMemTransportDescriptor*>(descriptor.get()) != nullptr) {
      ++shm;
    } else {
      ADD_FAILURE() << "unexpected transport in the localhost profile";
    }
  }
  EXPECT_EQ(udp, 1);
  EXPECT_EQ(shm, 1);
  const auto& builtin = qos.wire_protocol().builtin;
  ASSERT_FALSE(builtin.initialPeersList.empty());
  for (const auto& peer : builtin.initialPeersList) EXPECT_EQ(IPLocator::toIPv4string(peer), "127.0.0.1");
  for (const auto& loc : builtin.metatrafficUnicastLocatorList) EXPECT_EQ(IPLocator::toIPv4string(loc), "127.0.0.1");
}

// What a peer learns about us through discovery is the ground truth of where data would go.
class LocatorCollector : public eprosima::fastdds::dds::DomainParticipantListener {
 public:
  void on_participant_discovery(eprosima::fastdds::dds::DomainParticipant*,
                                eprosima::fastrtps::rtps::ParticipantDiscoveryInfo&& info) override {
    if (info.status != eprosima::fastrtps::rtps::ParticipantDiscoveryInfo::DISCOVERED_PARTICIPANT) return;
    if (info.info.m_participantName.to_string() != "announcer") return;
    std::lock_guard<std::mutex> lock(mutex);
    for (const auto& l : info.info.metatraffic_locators.unicast) locators.push_back(l);
    for (const auto& l : info.info.default_locators.unicast) locators.push_back(l);
    discovered = true;
    cv.notify_all();
  }
  std::mutex mutex;
  std::condition_variable cv;
  bool discovered = false;
  std::vector<Locator_t> locators;
};

TEST(LocalhostProfile, PeersOnlyLearnLoopbackOrSharedMemoryLocators) {
  using eprosima::fastdds::dds::DomainParticipantFactory;
  auto announcer = test::make_participant(test::kDomainLocalhostDiscovery, "announcer");
  LocatorCollector collector;
  auto* observer = DomainParticipantFactory::get_instance()->create_participant_with_profile(
      test::kDomainLocalhostDiscovery, "sarloc_localhost", &collector);
  ASSERT_NE(observer, nullptr);
  {
    std::unique_lock<std::mutex> lock(collector.mutex);
    collector.cv.wait_for(lock, std::chrono::seconds(10), [&] { return collector.discovered; });
    ASSERT_TRUE(collector.discovered) << "the two participants never discovered each other";
    ASSERT_FALSE(collector.locators.empty());
    for (const auto& l : collector.locators) {
      if (l.kind == LOCATOR_KIND_SHM) continue;
      EXPECT_EQ(l.kind, LOCATOR_KIND_UDPv4);
      EXPECT_EQ(IPLocator::toIPv4string(l), "127.0.0.1") << "announced a non-loopback locator";
    }
  }
  observer->set_listener(nullptr);
  DomainParticipantFactory::get_instance()->delete_participant(observer);
}

// A whole mission on one host has 7+ participants. Unicast discovery only reaches the
// well-known ports of maxInitialPeersRange participant ids, so the last ones to start must
// still find each other (this failed with Fast DDS's default range of 4).
TEST(LocalhostProfile, LateParticipantsOfABigMissionStillDiscoverEachOther) {
  std::vector<std::shared_ptr<Participant>> early;
  for (int i = 0; i < 6; ++i) {
    early.push_back(test::make_participant(test::kDomainManyParticipants, "early-" + std::to_string(i)));
  }
  auto late_writer_side = test::make_participant(test::kDomainManyParticipants, "late-writer");
  auto late_reader_side = test::make_participant(test::kDomainManyParticipants, "late-reader");
  test::Inbox<::sarloc::IncidentSummary> inbox;
  Reader<::sarloc::IncidentSummary> reader(late_reader_side, [&](const auto& s, const auto&) { inbox.push(s); });
  Writer<::sarloc::IncidentSummary> writer(late_writer_side);
  ASSERT_TRUE(writer.wait_for_readers(1, std::chrono::seconds(10)))
      << "participants 7 and 8 on one host never matched";
}

TEST(LocalhostProfile, UnknownProfileIsAClearError) {
  ParticipantConfig config;
  config.domain_id = test::kDomainWrongProfile;
  config.profile = "sarloc_no_such_profile";
  try {
    Participant participant(config);
    FAIL() << "expected DdsError";
  } catch (const DdsError& e) {
    EXPECT_NE(std::string(e.what()).find("sarloc_no_such_profile"), std::string::npos) << e.what();
  }
}

TEST(LocalhostProfile, InvalidConfigNamesTheField) {
  ParticipantConfig config;
  config.domain_id = 500;
  EXPECT_THROW(config.validate(), ConfigError);
  config.domain_id = 0;
  config.profiles_file = "/nonexistent.xml";
  try {
    config.validate();
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("dds.profiles_file = '/nonexistent.xml'"), std::string::npos);
  }
}

}  // namespace
}  // namespace sarloc::dds
