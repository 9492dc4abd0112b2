#pragma once
// One dipole fitted to a window of recent field samples at once (batch maximum likelihood), to
// check a sequential filter against what its latest samples say.
//
// A sequential filter that collapsed early on a wrong place near a victim keeps fitting the
// samples to come from there, linearised at its own mean: a victim 2.8 m deep was confirmed
// 1.2 m off with a 0.29 m radius while the samples fitted the truth far better (NIS 0.5-1.6
// against 4-8; docs/estimation/avalanche.md, "What the latest samples say"). A batch fit has no
// such memory: it re-linearises every sample at every iteration. The SOG filter fits its window
// of latest samples when a confirmation is asked (SogFilter::window_reaches) and tells how far
// from its estimate they alone allow the transmitter.
//
// Each sample's noise is set once, from the field measured (as FieldNoiseModel does where no
// prediction is at hand) and its range to a reference point: the deviance is then a weighted
// sum of squares, and deviances at two places differ by -2 log of their likelihood ratio. (With
// the noise taken from each place's own prediction, a weaker field pays less log-variance, and
// the fit drifts away from the truth even on noise-free samples.)
//
//   const DipoleWindowFit fit(model, samples, p_ref);
//   std::optional<DipoleFit> best = fit.fit(p0, m0);         // position and moment free
//   std::optional<DipoleFit> here = fit.fit_moment(p0, m0);  // position held at p0
//   double ratio = here->deviance - best->deviance;          // -2 log likelihood ratio
#include <cstdint>
#include <optional>
#include <vector>

#include "sarloc/core/avalanche/field_noise_model.hpp"
#include "sarloc/core/common/types.hpp"

namespace sarloc::avalanche {

/// One field sample, placed in the frame the fit works in.
struct WindowSample {
  Vec3 field = Vec3::Zero();         ///< as measured, receiver frame, invalid axes ignored
  Vec3 floor = Vec3::Zero();         ///< per-axis noise floor (FieldNoiseModel::floor)
  std::uint8_t axes = 0b111;         ///< bit a: axis a carries signal
  Mat3 rotation = Mat3::Identity();  ///< receiver frame -> fit frame
  Vec3 antenna = Vec3::Zero();       ///< antenna position in the fit frame (m)
  /// Variance (m^2, per axis) of `antenna`: odometry noise since the sample; the field's
  /// gradient turns it into field noise.
  double position_variance = 0.0;
};

/// What a fit found: the dipole, its deviance (the window's normalised sum of squares, -2
/// log-likelihood up to a constant), and the covariance of [p; m] from the Gauss-Newton Hessian.
struct DipoleFit {
  Vec3 position = Vec3::Zero();
  Vec3 moment = Vec3::Zero();
  double deviance = 0.0;
  Mat6 covariance = Mat6::Identity();
  int valid_axes = 0;  ///< observations in the window
};

/// The measurement model of the fit: the SOG filter's own (field_carrier_hz, noise, the
/// calibration's variances as white noise, which is conservative for a single sample).
struct DipoleFitModel {
  double wavenumber = 0.0;
  FieldNoiseModel noise;
  /// Variances of E in z = (I + E) h, row-major (SogConfig::calibration_variance); zero: none.
  Eigen::Matrix<double, 9, 1> calibration_variance = Eigen::Matrix<double, 9, 1>::Zero();
  int max_iterations = 30;
};

class DipoleWindowFit {
 public:
  /// Each sample's per-axis variance is fixed here, from its measured field and its range to
  /// `reference` (the place the fit is asked about; the antenna's position error matters by the
  /// field's gradient there).
  DipoleWindowFit(const DipoleFitModel& model, std::vector<WindowSample> samples, const Vec3& reference);

  /// Levenberg-Marquardt on [p; m] from (p0, m0), each sample read with the sign of the field
  /// that explains it best (a receiver measures +-h). nullopt: no valid observation, or the
  /// fit met a singular point (the antenna on the dipole).
  std::optional<DipoleFit> fit(const Vec3& p0, const Vec3& m0) const;
  /// The same with the position held at p0: the best the window can say of a dipole there.
  std::optional<DipoleFit> fit_moment(const Vec3& p0, const Vec3& m0) const;
  /// The window's deviance under (p, m); nullopt at a singular point or without an observation.
  std::optional<double> deviance(const Vec3& p, const Vec3& m) const;

 private:
  struct Normalised;
  std::optional<Normalised> normalise(const Vec3& p, const Vec3& m) const;
  std::optional<DipoleFit> solve(const Vec3& p0, const Vec3& m0, bool position_free) const;
  DipoleFitModel model_;
  std::vector<WindowSample> samples_;
  std::vector<Vec3> sigma_;  ///< per sample, per axis
  int rows_ = 0;             ///< valid axes in the window
};

}  // namespace sarloc::avalanche
