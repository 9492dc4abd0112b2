// The core daemon's VictimEstimate writer answers every measurement: its two workers writing at
// once never refuse an answer or file one under another rescuer's instance, and a reader that
// stops acknowledging never holds it back (docs/benchmarks.md, "Scale and soak": at 200
// rescuers, answers refused with RETCODE_TIMEOUT).
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <map>
#include <mutex>
#include <set>
#include <sstream>
#include <string>
#include <thread>

#include "sarloc/dds/conversions.hpp"
#include "sarloc/dds/reader.hpp"
#include "sarloc/dds/return_code.hpp"
#include "sarloc/dds/writer.hpp"
#include "support/dds_test_domains.hpp"
#include "support/dds_test_helpers.hpp"
#include "support/sample_messages.hpp"

namespace sarloc::dds {
namespace {

using namespace std::chrono_literals;

// One (rescuer, signal) is one instance whatever key was written before it: Fast DDS 2.9's
// generated key hash took three alignment bytes left over from the previous key
// (dds/key_hashed_type.hpp), and the core daemon's writer ran out of max_instances. Ids of 15
// and 16 characters, interleaved as two workers interleave them, from two threads.
TEST(EstimateWriter, EachKeyIsOneInstanceWhateverWasWrittenBeforeIt) {
  auto client = test::make_participant(test::kDomainEstimateStall, "client");
  std::mutex mutex;
  std::map<std::pair<std::string, std::uint32_t>, std::set<std::string>> handles;  // key -> instances seen
  Reader<::sarloc::VictimEstimate> reader(client, [&](const ::sarloc::VictimEstimate& e, const auto& info) {
    std::ostringstream handle;
    for (std::size_t i = 0; i < 16; ++i) handle << static_cast<int>(info.instance_handle.value[i]) << '.';
    std::lock_guard<std::mutex> lock(mutex);
    handles[{e.rescuer_id().to_string(), e.signal_id()}].insert(handle.str());
  });
  auto daemon = test::make_participant(test::kDomainEstimateStall, "core");
  Writer<::sarloc::VictimEstimate> writer(daemon);
  ASSERT_TRUE(writer.wait_for_readers(1, 15s));
  std::atomic<int> refused{0};
  auto worker = [&](int first_rescuer) {
    auto e = to_idl(test::sample_victim_estimate(), 0);
    for (std::uint64_t round = 1; round <= 10; ++round) {
      for (int r = first_rescuer; r < first_rescuer + 50; ++r) {
        for (std::uint32_t signal = 1; signal <= 3; ++signal) {
          e.rescuer_id("bench-rescuer-" + std::to_string(r));  // 15 characters below 10, 16 from 10
          e.signal_id(signal + static_cast<std::uint32_t>(round % 2));
          e.measurement_sequence(round);
          if (writer.write_returning(e) != eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK) refused.fetch_add(1);
        }
      }
    }
  };
  std::thread one(worker, 0), two(worker, 50);
  one.join();
  two.join();
  // A liveness bound, not a speed figure: 3000 reliable samples acknowledged (0.3 s alone). It
  // once failed in a fresh-clone CI run: the next test, then on this test's domain, had its
  // recorder stopped and killed, and this writer waited for it (2026-12-07; now on its own domain).
  ASSERT_TRUE(writer.wait_for_acknowledgments(10s));
  std::lock_guard<std::mutex> lock(mutex);
  EXPECT_EQ(refused.load(), 0);
  EXPECT_EQ(handles.size(), 400u) << "100 rescuers, signals 1-4";
  std::size_t extra = 0;
  for (const auto& [key, seen] : handles) extra += seen.size() - 1;
  EXPECT_EQ(extra, 0u) << "samples of one key filed under more than one instance";
}

TEST(EstimateWriter, AReaderThatStopsAcknowledgingNeverHoldsTheWriterBack) {
  // The reader: a recorder (every topic, RELIABLE), stopped once it has the first answer.
  const auto file = std::filesystem::temp_directory_path() / ("sarloc-stall-" + std::to_string(::getpid()) + ".mcap");
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    const std::string domain = std::to_string(static_cast<int>(test::kDomainEstimateStallReader));
    ::execl(SARLOC_BIN_DIR "/sarloc-record", "sarloc-record", "-c", SARLOC_SOURCE_DIR "/config/missions/default.yaml",
            "--domain", domain.c_str(), "-o", file.c_str(), "--duration", "60", "--log-level", "warn",
            static_cast<char*>(nullptr));
    ::_exit(127);
  }
  auto daemon = test::make_participant(test::kDomainEstimateStallReader, "core");
  Writer<::sarloc::VictimEstimate> writer(daemon);
  ASSERT_TRUE(writer.wait_for_readers(1, 15s));
  auto estimate = to_idl(test::sample_victim_estimate(), 1);
  ASSERT_TRUE(writer.write(estimate));
  ASSERT_TRUE(writer.wait_for_acknowledgments(5s));
  ::kill(pid, SIGSTOP);

  // One answer per measurement of the same (rescuer, signal), as the daemon writes them.
  int refused = 0;
  std::string codes;
  auto slowest = 0ms;
  for (std::uint64_t sequence = 2; sequence <= 11; ++sequence) {
    estimate.measurement_sequence(sequence);
    const auto start = std::chrono::steady_clock::now();
    const auto code = writer.write_returning(estimate);
    slowest = std::max(slowest,
                       std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - start));
    if (code != eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK) {
      ++refused;
      codes += std::string(" ") + return_code_name(code);
    }
    std::this_thread::sleep_for(20ms);
  }
  ::kill(pid, SIGKILL);
  ::kill(pid, SIGCONT);
  int status = 0;
  ::waitpid(pid, &status, 0);
  std::filesystem::remove(file);
  EXPECT_EQ(refused, 0) << "refused:" << codes;
  EXPECT_LT(slowest, 50ms) << "a write waited for the stopped reader's acknowledgement";
}

}  // namespace
}  // namespace sarloc::dds
