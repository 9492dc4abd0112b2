// Negative information (issue 12): a pulse that was due and not heard. The detection model
// against the detector it stands for, the separation's misses, the filter's miss update and
// what the rescuer's search does with one.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "sarloc/core/avalanche/beacon_receiver.hpp"
#include "sarloc/core/avalanche/detection_curve.hpp"
#include "sarloc/core/avalanche/pulse_detector.hpp"
#include "sarloc/core/avalanche/rescuer_search.hpp"
#include "sarloc/core/avalanche/simulator.hpp"
#include "sarloc/core/avalanche/sog_filter.hpp"
#include "sarloc/core/common/chi_square.hpp"
#include "sarloc/core/common/errors.hpp"

namespace sarloc::avalanche {
namespace {

// The threshold the detector applies to a tracked carrier's band in a window of n samples
// (pulse_detector.cpp: false alarms per window spread over its tests).
double tracked_threshold(const PulseDetectorConfig& c, double window_s, double sample_rate_hz) {
  const double freqs = std::floor(2.0 * c.tracked_band_hz / c.coarse_step_hz) + 1.0;
  return chi_square_quantile(1.0 - c.false_alarms_per_window / (freqs * window_s * sample_rate_hz), 6.0);
}

TEST(DetectionCurve, IsTheChiSquareTailAndRisesWithThePulse) {
  const DetectionCurve curve(40.0);
  EXPECT_NEAR(curve.probability(0.0), 1.0 - chi_square_cdf(40.0, 6.0), 1e-12);
  double last = curve.probability(0.0);
  for (double lambda : {10.0, 30.0, 40.0, 60.0, 100.0, 200.0}) {
    const double p = curve.probability(lambda);
    EXPECT_GT(p, last) << lambda;
    last = p;
  }
  // Mean of the statistic 6 + lambda at the threshold: about even odds.
  EXPECT_NEAR(curve.probability(34.0), 0.5, 0.08);
  EXPECT_GT(curve.probability(150.0), 0.9999);
  EXPECT_THROW(DetectionCurve(-1.0), ConfigError);
}

// The filter's default threshold says no more than the detector: it is at least the tracked
// band's threshold for the longest window a device listens (2 s, SimulatedRescuer's clamp).
TEST(DetectionCurve, DefaultThresholdCoversTheDetectorsWindows) {
  const PulseDetectorConfig detector;
  EXPECT_GE(SogConfig{}.miss_detection_statistic, tracked_threshold(detector, 2.0, 500.0));
  EXPECT_LT(SogConfig{}.miss_detection_statistic, tracked_threshold(detector, 2.0, 500.0) + 1.0);
}

// The model against the detector it stands for: pulses of known noncentrality on a tracked
// carrier are detected at the rate the curve predicts (measured: 0.28 / 0.73 / 0.93 against
// 0.19 / 0.66 / 0.96 at lambda 25 / 40 / 60; the detector also tries every 70 ms position and
// nearby carriers). The filter discounts lambda by miss_power_margin on top.
TEST(DetectionCurve, MatchesTheDetectorOnATrackedCarrier) {
  std::mt19937_64 rng(17);
  const Vec3 noise(2.1e-9, 6.3e-9, 6.3e-9);
  const PulseDetectorConfig detector;
  const DetectionCurve curve(tracked_threshold(detector, 1.0, 500.0));
  const double carrier = 12.0;
  const Vec3 direction = Vec3(1.0, 0.4, -0.3).normalized();
  for (double lambda : {25.0, 40.0, 60.0}) {
    // lambda = sum (a_i / noise_i)^2 for amplitude a = s * direction.
    const double s = std::sqrt(lambda / direction.cwiseQuotient(noise).squaredNorm());
    int detected = 0;
    constexpr int kWindows = 60;
    for (int k = 0; k < kWindows; ++k) {
      IncomingPulse p;
      p.start_s = 0.4;
      p.end_s = 0.47;
      p.carrier_offset_hz = carrier;
      p.amplitude = (s * direction).cast<std::complex<double>>() * std::polar(1.0, 0.37 * k);
      const BasebandWindow w = synthesize({p}, 0.0, 1.0, 500.0, noise, rng);
      for (const auto& d : detect_pulses(w, detector, {carrier})) {
        if (std::fabs(d.carrier_offset_hz - carrier) < 3.0 && d.end_s > p.start_s && d.start_s < p.end_s) {
          ++detected;
          break;
        }
      }
    }
    const double rate = static_cast<double>(detected) / kWindows;
    const double model = curve.probability(lambda);
    EXPECT_GE(rate, model - 0.15) << "lambda " << lambda;
    EXPECT_LE(rate, model + 0.2) << "lambda " << lambda;
  }
}

Beacon beacon_at(const Vec3& position, double period_s, double carrier_hz) {
  Beacon b;
  b.position = position;
  b.moment = Vec3(0.01, 0.004, 0.006);
  b.timing.period_s = period_s;
  b.timing.on_time_s = 0.1;
  b.timing.first_start_s = 0.23;
  b.timing.carrier_offset_hz = carrier_hz;
  return b;
}

// A tracked transmitter whose pulses stop (out of range) is reported missed, with the pulse
// floor of each axis; one heard, or one whose pulse could hide under another's, is not.
TEST(SignalSeparator, ReportsAPulseDueAndNotHeard) {
  SimulationConfig config;
  BeaconReceiver receiver(config, 3);
  ReceiverPose pose;
  pose.position = Vec3(0.0, 0.0, 1.0);
  std::vector<Beacon> beacons{beacon_at(Vec3(20.0, 5.0, -1.0), 0.8, -30.0)};
  std::uint32_t id = 0;
  for (int k = 0; k < 5; ++k) {
    const Listening heard = receiver.listen(pose, beacons, k, 1.0);
    EXPECT_TRUE(heard.report.misses.empty()) << "window " << k;
    for (const auto& h : heard.samples) id = h.sample.signal_id;
  }
  ASSERT_NE(id, 0U);
  beacons[0].position = Vec3(2000.0, 0.0, -1.0);  // silent from here on
  const Listening silent = receiver.listen(pose, beacons, 5, 1.0);
  EXPECT_TRUE(silent.samples.empty());
  ASSERT_EQ(silent.report.misses.size(), 1U);
  EXPECT_EQ(silent.report.misses[0].signal_id, id);
  EXPECT_EQ(silent.report.misses[0].valid_axes, 0);
  EXPECT_NEAR(silent.report.misses[0].noise.x(), config.field_noise_floor_A_per_m, 1e-12);
  const auto as_measurements = to_measurements(silent, "r1", 6, 6'000'000'000, std::nullopt);
  ASSERT_EQ(as_measurements.size(), 1U);
  EXPECT_EQ(as_measurements[0].valid_axes, 0);
  EXPECT_EQ(as_measurements[0].signal_id, id);
  // Another transmitter pulsing in the window (another carrier): a weak pulse under it could be
  // lost to the detector's dynamic range, so nothing is said of the silent one.
  beacons.push_back(beacon_at(Vec3(3.0, 1.0, -1.0), 0.9, 40.0));
  const Listening covered = receiver.listen(pose, beacons, 6, 1.0);
  for (const auto& m : covered.report.misses) EXPECT_NE(m.signal_id, id);
}

// A weak transmitter (48 m, pulses' edges tens of ms off) goes silent: its timing gate soon
// spans more than a window, so no single window proves a whole pulse was due; its carrier's
// silence across windows does (QuietSpan), and misses keep coming for minutes. Without the span
// they stopped within 140-175 windows on these seeds (0-1 in the last 60).
TEST(SignalSeparator, KeepsReportingMissesWhenTheTimingGateOutgrowsTheWindow) {
  for (std::uint64_t seed : {1U, 2U, 3U}) {
    SimulationConfig config;
    config.receiver.kind = ReceiverKind::kRealistic;
    BeaconReceiver receiver(config, seed);
    ReceiverPose pose;
    pose.position = Vec3(0.0, 0.0, 1.0);
    std::vector<Beacon> beacons{beacon_at(Vec3(48.0, 0.0, -1.5), 0.95, 20.0)};
    int k = 0;
    std::uint32_t id = 0;
    for (; k < 30; ++k) {
      for (const auto& h : receiver.listen(pose, beacons, k, 1.0).samples) id = h.sample.signal_id;
    }
    ASSERT_NE(id, 0U) << "seed " << seed;
    beacons[0].position = Vec3(3000.0, 0.0, -1.5);
    int late_misses = 0;
    for (int j = 0; j < 200; ++j, ++k) {
      const Listening silent = receiver.listen(pose, beacons, k, 1.0);
      ASSERT_LE(silent.report.misses.size(), 1U);
      if (j >= 140 && !silent.report.misses.empty()) {
        EXPECT_EQ(silent.report.misses[0].signal_id, id);
        ++late_misses;
      }
    }
    EXPECT_GE(late_misses, 10) << "seed " << seed;
  }
}

SogFilter initialised_filter(const Scenario& scenario) {
  SogFilter f;
  AvalancheSimulator sim(SimulationConfig{}, scenario, 5);
  f.process(sim.measure());
  return f;
}

FieldMeasurement miss_at(std::uint64_t sequence) {
  FieldMeasurement m;
  m.sequence = sequence;
  m.stamp = static_cast<TimestampNs>(sequence) * 1'000'000'000;
  m.field = Vec3::Zero();
  m.noise_stddev = Vec3(2.1e-9, 6.3e-9, 6.3e-9);
  m.valid_axes = 0;
  return m;
}

double weight_within(const SogFilter& f, double lo_m, double hi_m) {
  double w = 0.0;
  for (const auto& c : f.components()) {
    const double r = c.x.segment<3>(idx::kPos).head<2>().norm();
    if (r >= lo_m && r < hi_m) w += std::exp(c.log_weight);
  }
  return w;
}

// Heard 36 m away, then not heard after a 15 m walk east: the hypotheses now within 25 m
// (where a transmitter of the standard is heard) lose nearly all their weight, the ring's far
// side keeps its share, and the filter's frame and the place last heard move with the rescuer.
TEST(SogFilterMiss, WhereThePulseWouldHaveBeenHeardTheTransmitterIsNot) {
  Scenario s;
  s.transmitter = Vec3(30.0, 20.0, -1.5);
  s.moment = Vec3(0.01, -0.005, 0.012);
  s.receiver = Vec3(0.0, 0.0, 1.0);
  s.receiver_rpy = Vec3(0.0, 0.0, 0.0);
  SogFilter f = initialised_filter(s);
  const std::uint64_t steps = f.steps();
  Odometry o;
  o.sequence = 1;
  o.interval_start = 0;
  o.interval_end = 1'000'000'000;
  o.translation = Vec3(15.0, 0.0, 0.0);
  o.covariance = Mat6::Identity() * 1e-4;
  f.add_odometry(o);
  const Vec3 heard_before = f.predicted_last_measurement_position();
  FieldMeasurement m = miss_at(2);
  const SogStepResult r = f.process(m);
  EXPECT_TRUE(r.miss);
  EXPECT_EQ(f.steps(), steps);  // no measurement of the field
  EXPECT_EQ(f.estimate().stamp, m.stamp);
  EXPECT_LT((f.predicted_last_measurement_position() - heard_before).norm(), 1e-6);
  EXPECT_NEAR(heard_before.x(), -15.0, 0.1);
  EXPECT_LT(weight_within(f, 0.0, 25.0), 0.01);
  EXPECT_GT(weight_within(f, 45.0, 1e9), 0.5);
}

TEST(SogFilterMiss, TurnedOffOrBeforeTheFirstPulseItChangesNothing) {
  SogFilter fresh;
  const SogStepResult r = fresh.process(miss_at(1));
  EXPECT_FALSE(fresh.initialised());
  EXPECT_FALSE(r.miss);
  SogConfig off;
  off.negative_information = false;
  Scenario s;
  s.transmitter = Vec3(30.0, 20.0, -1.5);
  s.moment = Vec3(0.01, -0.005, 0.012);
  s.receiver = Vec3(0.0, 0.0, 1.0);
  SogFilter f(off);
  AvalancheSimulator sim(SimulationConfig{}, s, 5);
  f.process(sim.measure());
  const auto before = f.components().size();
  const double w0 = f.components().front().log_weight;
  EXPECT_FALSE(f.process(miss_at(2)).miss);
  EXPECT_EQ(f.components().size(), before);
  EXPECT_EQ(f.components().front().log_weight, w0);
  FieldMeasurement bad = miss_at(3);
  bad.valid_axes = 8;
  EXPECT_THROW(f.process(bad), InputError);
}

// The floor: a miss where every hypothesis says "heard" (a pulse lost to interference, next to
// the transmitter) cannot erase the mixture or reorder it by more than miss_weight_floor.
TEST(SogFilterMiss, AMissNoHypothesisForesawLeavesTheMixture) {
  Scenario s;
  s.transmitter = Vec3(4.0, 1.0, -1.5);
  s.moment = Vec3(0.01, -0.005, 0.012);
  s.receiver = Vec3(0.0, 0.0, 1.0);
  SogFilter f = initialised_filter(s);
  const auto before = f.moments().mean;
  const SogStepResult r = f.process(miss_at(2));
  EXPECT_TRUE(r.miss);
  ASSERT_TRUE(f.initialised());
  EXPECT_LT((f.moments().mean.segment<3>(idx::kPos) - before.segment<3>(idx::kPos)).norm(), 1.0);
}

FieldMeasurement heard(AvalancheSimulator& sim, std::uint64_t sequence) {
  FieldMeasurement m = sim.measure();
  m.rescuer_id = "r1";
  m.sequence = sequence;
  m.stamp = static_cast<TimestampNs>(sequence) * 1'000'000'000;
  return m;
}

// The rescuer's search: a miss of a signal it never heard is nothing; one of its target
// carries coast guidance and never raises the status.
TEST(RescuerSearchMiss, UpdatesTheFilterNeverTheStatusAndGuidesOn) {
  RescuerSearch search("r1", RescuerSearchConfig{});
  FieldMeasurement unknown = miss_at(1);
  unknown.rescuer_id = "r1";
  unknown.signal_id = 9;
  const auto nothing = search.process(unknown);
  ASSERT_TRUE(std::holds_alternative<SearchUpdate>(nothing));
  EXPECT_FALSE(std::get<SearchUpdate>(nothing).estimate.has_value());
  EXPECT_EQ(search.signal_count(), 0U);

  Scenario s;
  s.transmitter = Vec3(30.0, 20.0, -1.5);
  s.moment = Vec3(0.01, -0.005, 0.012);
  s.receiver = Vec3(0.0, 0.0, 1.0);
  AvalancheSimulator sim(SimulationConfig{}, s, 5);
  FieldMeasurement first = heard(sim, 2);
  first.signal_id = 1;
  ASSERT_TRUE(std::holds_alternative<SearchUpdate>(search.process(first)));
  const auto status_before = search.estimate(1)->status;
  FieldMeasurement miss = miss_at(3);
  miss.rescuer_id = "r1";
  miss.signal_id = 1;
  const auto out = search.process(miss);
  ASSERT_TRUE(std::holds_alternative<SearchUpdate>(out));
  const auto& update = std::get<SearchUpdate>(out);
  ASSERT_TRUE(update.estimate.has_value());
  EXPECT_LE(update.estimate->status, status_before);
  EXPECT_EQ(update.estimate->stamp, miss.stamp);
  ASSERT_TRUE(update.guidance.has_value());
  EXPECT_EQ(update.guidance->signal_id, 1U);
  // The same miss again is a duplicate, refused like any sample.
  EXPECT_TRUE(std::holds_alternative<Rejection>(search.process(miss)));
}

}  // namespace
}  // namespace sarloc::avalanche
