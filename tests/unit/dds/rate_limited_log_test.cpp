// RateLimitedLog stays bounded whoever floods it, and still says what it suppressed.
#include "sarloc/dds/rate_limited_log.hpp"

#include <gtest/gtest.h>
#include <spdlog/sinks/ostream_sink.h>

#include <sstream>
#include <thread>

namespace sarloc::dds {
namespace {

using namespace std::chrono_literals;

class CapturedLog {
 public:
  CapturedLog() : previous_(spdlog::default_logger()) {
    spdlog::set_default_logger(std::make_shared<spdlog::logger>(
        "captured", std::make_shared<spdlog::sinks::ostream_sink_mt>(out_)));
  }
  ~CapturedLog() { spdlog::set_default_logger(previous_); }
  std::string text() const { return out_.str(); }

 private:
  std::ostringstream out_;
  std::shared_ptr<spdlog::logger> previous_;
};

TEST(RateLimitedLog, OneLinePerSourceAndReasonPerInterval) {
  CapturedLog log;
  RateLimitedLog warnings(1h);
  for (int i = 0; i < 10; ++i) warnings.warn("r1", "invalid_value", "bad r1");
  warnings.warn("r2", "invalid_value", "bad r2");
  const auto text = log.text();
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 2) << text;
  EXPECT_EQ(warnings.sources(), 2U);
}

TEST(RateLimitedLog, AHundredThousandSourcesShareOneEntryOnceFull) {
  CapturedLog log;
  RateLimitedLog warnings(1h, 64);
  for (int k = 0; k < 100000; ++k) warnings.warn("intruder-" + std::to_string(k), "unknown_rescuer", "unknown");
  EXPECT_EQ(warnings.sources(), 65U) << "64 sources and the shared '(other sources)' entry";
  const auto text = log.text();
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 65) << "one line per entry, the rest suppressed";
}

TEST(RateLimitedLog, QuietSourcesAreForgottenWithTheirSuppressedCount) {
  CapturedLog log;
  // 300 ms: the second warning must come within it even on arm64 under qemu on a loaded machine
  // (20 ms failed there once: it was logged, not suppressed).
  RateLimitedLog warnings(300ms, 2);
  warnings.warn("a", "late", "late a");
  warnings.warn("a", "late", "late a");  // suppressed
  warnings.warn("b", "late", "late b");
  std::this_thread::sleep_for(400ms);
  warnings.warn("c", "late", "late c");  // table full: a and b are quiet and go
  EXPECT_EQ(warnings.sources(), 1U);
  EXPECT_NE(log.text().find("1 more 'late' from 'a' suppressed"), std::string::npos) << log.text();
}

}  // namespace
}  // namespace sarloc::dds
