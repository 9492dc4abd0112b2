// An orderly stop said on DDS (sign_off.hpp, docs/operations.md "Signing off"): a core daemon
// and an incident-command instance that stop in order dispose of their own NodeStatus instance
// before their writers go, so a reader can tell a stop from a loss; a node that is simply
// deleted (as a crash or an error exit leaves it) disposes of nothing.
#include <gtest/gtest.h>

#include <mutex>
#include <set>
#include <string>

#include "sarloc/dds/command_node.hpp"
#include "sarloc/dds/core_node.hpp"
#include "sarloc/dds/reader.hpp"
#include "support/dds_test_domains.hpp"
#include "support/dds_test_helpers.hpp"

namespace sarloc::dds {
namespace {

using namespace std::chrono_literals;
using test::eventually;

// Every NodeStatus: which nodes were heard and which disposed of their instance.
class StatusWatch {
 public:
  explicit StatusWatch(std::shared_ptr<Participant> participant) {
    ReaderEvents events;
    events.on_instance_gone = [this](const auto& info) {
      std::lock_guard<std::mutex> lock(mutex_);
      if (info.instance_state != eprosima::fastdds::dds::NOT_ALIVE_DISPOSED_INSTANCE_STATE) return;
      for (const auto& [handle, node] : nodes_) {
        if (handle == info.instance_handle) disposed_.insert(node);
      }
    };
    reader_ = std::make_unique<Reader<::sarloc::NodeStatus>>(
        std::move(participant),
        [this](const ::sarloc::NodeStatus& s, const auto& info) {
          std::lock_guard<std::mutex> lock(mutex_);
          nodes_.emplace_back(info.instance_handle, s.node_id().to_string());
        },
        EndpointOptions{}, events);
  }
  bool heard(const std::string& node) {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& [handle, id] : nodes_) {
      if (id == node) return true;
    }
    return false;
  }
  bool disposed(const std::string& node) {
    std::lock_guard<std::mutex> lock(mutex_);
    return disposed_.count(node) != 0;
  }

 private:
  std::mutex mutex_;
  std::vector<std::pair<eprosima::fastrtps::rtps::InstanceHandle_t, std::string>> nodes_;
  std::set<std::string> disposed_;
  std::unique_ptr<Reader<::sarloc::NodeStatus>> reader_;
};

TEST(SignOff, ADaemonAndIncidentCommandStoppedInOrderSaySoAndDeletedOnesDoNot) {
  StatusWatch watch(test::make_participant(test::kDomainSignOff, "watch"));
  CoreNodeConfig core_config;
  core_config.node_id = "core-signing-off";
  core_config.status_period_s = 0.2;
  CommandNodeConfig command_config;
  command_config.node_id = "command-signing-off";
  command_config.incident.incident_id = "sign-off-test";
  command_config.cycle_s = 0.1;
  const MissionClock clock;
  auto core = std::make_unique<CoreNode>(test::make_participant(test::kDomainSignOff, "core"), core_config);
  auto command = std::make_unique<CommandNode>(test::make_participant(test::kDomainSignOff, "command"), command_config, clock);
  ASSERT_TRUE(eventually([&] { return watch.heard("core-signing-off") && watch.heard("command-signing-off"); }, 10s));

  EXPECT_TRUE(core->sign_off(2s));
  EXPECT_TRUE(command->sign_off(2s));
  EXPECT_TRUE(eventually([&] { return watch.disposed("core-signing-off") && watch.disposed("command-signing-off"); }, 5s));
  core.reset();
  command.reset();

  // Deleted without signing off (what a crash or an error exit leaves): nothing disposed.
  core_config.node_id = "core-deleted";
  command_config.node_id = "command-deleted";
  core = std::make_unique<CoreNode>(test::make_participant(test::kDomainSignOff, "core2"), core_config);
  command = std::make_unique<CommandNode>(test::make_participant(test::kDomainSignOff, "command2"), command_config, clock);
  ASSERT_TRUE(eventually([&] { return watch.heard("core-deleted") && watch.heard("command-deleted"); }, 10s));
  core.reset();
  command.reset();
  std::this_thread::sleep_for(1s);
  EXPECT_FALSE(watch.disposed("core-deleted"));
  EXPECT_FALSE(watch.disposed("command-deleted"));
}

}  // namespace
}  // namespace sarloc::dds
