#pragma once
// Particle-filter baselines for one avalanche transmitter (seed 000, section IV), robocentric
// like the SOG filter, on the TransmitterFilter interface. One implementation, three rows of
// the comparison (FilterKind):
//   kPf            vanilla PF (Algorithm 2): each particle samples the full state [Psi, p, m];
//                  the static moment gets the artificial process noise the paper tried
//                  (moment_noise_relative), or particles would never move off their initial m;
//   kRbpf          Rao-Blackwellized PF (Algorithm 3, eq. (19)): particles over [Psi, p], one
//                  Kalman filter per particle on m, exact because z = C(Psi, p) m is linear in m;
//                  resampling when N_eff (eq. (20)) falls below resample_ess_fraction N;
//   kRbpfImproved  the RBPF against its failure mode, depletion (section V: 25 of 100 trials
//                  more than 1 m off): regularised resampling, and a rebuild from the current
//                  sample when no particle explains the recent samples (docs/estimation/baselines.md).
// Every kind uses the measurement model the SOG filter uses (dipole_model.hpp, noise
// relative |h| + floor per axis, invalid axes left out, the sign-invariant likelihood
// (N(z; h, S) + N(-z; h, S)) / 2), the attitude readings as a likelihood on Psi, and the pulses
// due and not heard (DetectionCurve). Particles start as draws from the SOG filter's initial
// mixture (seed 000, section IV: "generated in a similar way to the one described in III-B").
//
//   ParticleFilter f(FilterKind::kRbpf, SogConfig{}, ParticleFilterConfig{}, seed);
//   f.add_odometry(odo);
//   FilterStepResult r = f.update(measurement);
#include <cstdint>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "sarloc/core/avalanche/detection_curve.hpp"
#include "sarloc/core/avalanche/filter_kind.hpp"
#include "sarloc/core/avalanche/odometry_accumulator.hpp"
#include "sarloc/core/avalanche/sog_filter.hpp"
#include "sarloc/core/avalanche/transmitter_filter.hpp"

namespace sarloc::avalanche {

struct ParticleFilterConfig {
  std::uint32_t particles = 5000;        ///< seed 000 section V: 5000 particles throughout
  /// Resample when N_eff < this fraction of the particle count (seed 000 eq. (20)).
  double resample_ess_fraction = 0.5;
  /// Vanilla PF: sigma of the artificial process noise on each moment component per update,
  /// relative to |m| (seed 000 section IV, after ref. [12]).
  double moment_noise_relative = 0.02;
  // --- improved RBPF ---
  std::uint32_t improved_particles = 4500;  ///< the improved RBPF's count: 10 % fewer pays for its regularisation pass
  /// Regularised resampling (Musso, Oudjane, Le Gland 2001) with the Liu-West shrinkage: each
  /// copy's position is moved by a Gaussian kernel of covariance h^2 times the cloud's, h =
  /// this times Silverman's rule for 3 dimensions (0.29 at 4500 particles), and pulled towards
  /// the cloud's mean by 1 - sqrt(1 - h^2), so the copies of one ancestor spread over the
  /// posterior's width while the cloud keeps its mean and covariance. 0 = off.
  double regularisation_scale = 1.0;
  /// ... only while the cloud's 95 % radius is below this: the shrinkage pulls a ring or two
  /// arcs towards a mean between them (measured in docs/estimation/baselines.md).
  double regularise_below_radius_m = 5.0;
  /// Rebuild from the current sample when the sum of the predictive NIS of the last
  /// SogConfig::divergence_window updates exceeds its gate (the SOG filter's divergence test).
  bool rebuild_on_divergence = true;

  /// Throws ConfigError "particle.<key> = value: rule".
  void validate() const;
};

class ParticleFilter : public TransmitterFilter {
 public:
  /// kind: kPf, kRbpf or kRbpfImproved (ConfigError otherwise). `seed` drives every draw.
  ParticleFilter(FilterKind kind, SogConfig sog, ParticleFilterConfig config, std::uint64_t seed,
                 std::string rescuer_id = {}, std::uint32_t signal_id = 0);

  std::string kind() const override { return to_string(kind_); }
  void add_odometry(const Odometry& odometry) override;
  FilterStepResult update(const FieldMeasurement& measurement) override;
  bool initialised() const override { return !particles_.empty(); }
  std::size_t size() const override { return particles_.size(); }
  MixtureMoments moments() const override;
  MixtureMoments predicted_moments() const override;
  Vec3 predicted_last_measurement_position() const override;
  VictimEstimate estimate(std::size_t top_k = 5) const override;
  std::vector<TransmitterHypothesis> hypotheses() const override;
  const InnovationRecord& innovations() const override { return record_; }
  std::uint64_t mixture_samples() const override { return mixture_samples_; }
  bool moment_plausible() const override;
  FieldNoiseModel noise() const override { return sog_.noise(); }
  double converged_radius_m() const override { return sog_.converged_radius_m; }

  /// Effective sample size after the latest update (eq. (20)), before any resampling.
  double last_effective_sample_size() const { return last_ess_; }
  std::uint64_t resamplings() const { return resamplings_; }
  std::uint64_t rebuilds() const { return rebuilds_; }

 private:
  struct Particle {
    Mat3 rotation = Mat3::Identity();  ///< R_k in G_k (its rpy only when moments are asked for)
    Vec3 p = Vec3::Zero();    ///< transmitter in G_k
    Vec3 m = Vec3::Zero();    ///< moment (RBPF: the Kalman mean)
    Mat3 M = Mat3::Zero();    ///< RBPF: the Kalman covariance of m; vanilla: 0
    double log_w = 0.0;
  };

  void initialise(const FieldMeasurement& measurement);
  /// Moves a particle by its own draw d of the displacement (and the vanilla PF's moment noise).
  void propagate(Particle& particle, const DispVec& d);
  /// Propagation, the attitude reading and the field sample (weights and, for the RBPF, the
  /// Kalman updates of m) in one pass; returns the cloud's predictive NIS (PredictiveMoments).
  double propagate_and_weigh(const Displacement& disp, const OrientationObservation* orientation,
                             const FieldMeasurement& measurement);
  void weigh_miss(const Vec3& floor);
  /// Normalises, records N_eff, resamples below the threshold, and regularises the improved
  /// RBPF's copies.
  bool normalise_and_resample();
  void regularise();
  /// The position block of moments(), from the cache when there is one.
  Mat3 position_covariance() const;
  bool rao_blackwellized() const { return kind_ != FilterKind::kPf; }

  FilterKind kind_;
  SogConfig sog_;
  ParticleFilterConfig config_;
  std::uint32_t count_;
  std::string rescuer_id_;
  std::uint32_t signal_id_;
  std::mt19937_64 rng_;
  std::vector<Particle> particles_;
  OdometryAccumulator odometry_;
  DetectionCurve detection_;
  InnovationRecord record_;
  std::optional<std::uint64_t> last_sequence_;
  TimestampNs last_stamp_ = 0;
  Vec3 heard_at_ = Vec3::Zero();
  std::uint64_t mixture_samples_ = 0;
  double last_ess_ = 0.0;
  std::uint64_t resamplings_ = 0;
  std::uint64_t rebuilds_ = 0;
  /// moments() of the current particles: the search control asks for them several times a step.
  mutable std::optional<MixtureMoments> moments_;
};

}  // namespace sarloc::avalanche
