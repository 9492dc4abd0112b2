#include "trial_trace.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "sarloc/core/avalanche/bearing_density.hpp"
#include "sarloc/core/common/gaussian.hpp"
#include "sarloc/core/common/position_nees.hpp"

namespace sarloc::eval {
namespace av = sarloc::avalanche;

namespace {
double bearing_of(const Vec3& relative) { return std::atan2(relative.y(), relative.x()); }
}  // namespace

void print_trace_step(const av::TrialStep& s) {
  if (s.step == 1) {
    const auto& sc = s.sim.scenario();
    std::printf("trial %u: transmitter [%.2f %.2f %.2f] |m| %.4f m [%.3f %.3f %.3f]\n", s.trial,
                sc.transmitter.x(), sc.transmitter.y(), sc.transmitter.z(), sc.moment.norm(),
                sc.moment.x() / sc.moment.norm(), sc.moment.y() / sc.moment.norm(),
                sc.moment.z() / sc.moment.norm());
  }
  const Vec3 truth = s.sim.true_relative_position();
  const Vec3 err = s.estimate.relative.position - truth;
  const double nees = sarloc::position_nees(err, s.estimate.relative.covariance);
  const std::vector<av::TransmitterHypothesis> hypotheses = s.filter.hypotheses();
  double w0 = 0.0;
  for (const av::TransmitterHypothesis& h : hypotheses) w0 = std::max(w0, h.weight);
  std::printf("%3u mode %d |z| %.2e true [%6.2f %6.2f %5.2f] est [%6.2f %6.2f %5.2f] err %.2f "
              "r95 %.2f n %5zu nis %.1f w0 %.2f nees %.1f P45 %.2f%s\n",
              s.step, static_cast<int>(s.guidance.mode), s.measurement.field.norm(), truth.x(),
              truth.y(), truth.z(), s.estimate.relative.position.x(),
              s.estimate.relative.position.y(), s.estimate.relative.position.z(), err.norm(),
              sarloc::radius95_3d(s.estimate.relative.covariance), s.filter.size(),
              s.filter_result.min_nis, w0, nees,
              av::bearing_agreement(hypotheses, bearing_of(truth)).mass_within_45deg,
              s.filter_result.reinitialised ? " REINIT" : "");
}

av::MultiBurialTraceObserver multi_burial_trace_printer() {
  av::MultiBurialTraceObserver o;
  o.victims = [](const std::vector<av::MultiBurialTraceVictim>& victims) {
    for (std::size_t v = 0; v < victims.size(); ++v) {
      const av::MultiBurialTraceVictim& t = victims[v];
      std::printf("victim %zu at [%.2f %.2f %.2f] |m| %.4f period %.4f s on %.3f s first %.4f s carrier %+.2f Hz\n",
                  v, t.position.x(), t.position.y(), t.position.z(), t.moment_am2, t.timing.period_s,
                  t.timing.on_time_s, t.timing.first_start_s, t.timing.carrier_offset_hz);
    }
  };
  o.step = [](const av::MultiBurialTraceStep& s) {
    for (const av::MultiBurialTraceSample& t : s.samples) {
      std::printf("    signal %u axes %u of victim %s", t.signal_id, static_cast<unsigned>(t.valid_axes),
                  t.majority_victim ? std::to_string(*t.majority_victim).c_str() : "-");
      if (t.pulse_victim) std::printf(" pulse %zu", *t.pulse_victim);
      if (t.mixed_victim) std::printf("+%zu(%.2f)", *t.mixed_victim, t.mixed_energy_ratio);
      if (t.truth_nis) std::printf(" truth-nis %.1f", *t.truth_nis);
      if (t.filter_nis) std::printf(" filter-nis %.1f", *t.filter_nis);
      if (t.estimate) {
        std::printf(" status %d at [%.2f %.2f %.2f] r95 %.2f repeat %d", static_cast<int>(t.estimate->status),
                    t.estimate_at.x(), t.estimate_at.y(), t.estimate_at.z(),
                    sarloc::radius95_3d(t.estimate->relative.covariance), static_cast<int>(t.estimate->repeat));
        if (t.error_m) std::printf(" err %.2f nees %.1f", *t.error_m, *t.nees);
      }
      if (t.guidance) std::printf(" guides mode %d", static_cast<int>(t.guidance->mode));
      std::printf("\n");
    }
    std::printf("%4u rescuer [%.2f %.2f] target %s found %u unattributed %u", s.step, s.rescuer.x(), s.rescuer.y(),
                s.target ? std::to_string(*s.target).c_str() : "-", s.found, s.unattributed_pulses);
    if (s.guidance)
      std::printf(" walks mode %d %.2f m bearing %+.2f", static_cast<int>(s.guidance->mode), s.guidance->step_m,
                  s.guidance->bearing_rad);
    std::printf("\n");
  };
  return o;
}

const char* TraceCsv::header() {
  return "trial,step,mode,tx_w,ty_w,tz_w,rx_w,ry_w,rz_w,roll,pitch,yaw,zx_r,zy_r,zz_r,"
         "est_x_g,est_y_g,est_z_g,r95_h,components,mass_within_45deg,mean_cosine,heading_cosine,"
         "status,valid_axes,err_x_r,err_y_r,err_z_r,sd_x_r,sd_y_r,sd_z_r,nees\n";
}

void TraceCsv::add(const av::TrialStep& s) {
  const auto& sc = s.sim.scenario();
  const double tb = bearing_of(s.sim.true_relative_position());
  const av::BearingAgreement a = av::bearing_agreement(s.filter.hypotheses(), tb);
  const Vec3& est = s.estimate.relative.position;
  const double heading_cos = s.guidance.step_m > 0.0 ? std::cos(s.guidance.heading_rad - tb) : 0.0;
  // The error and its stated spread per axis, so that a NEES outside its bounds can be traced
  // to the axis and the range where the filter is overconfident.
  const Mat3& P = s.estimate.relative.covariance;
  const Vec3 err = est - s.sim.true_relative_position();
  const double nees = sarloc::position_nees(err, P);
  char line[800];
  std::snprintf(line, sizeof line,
                "%u,%u,%d,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.6f,%.6f,%.6f,%.6e,%.6e,%.6e,"
                "%.4f,%.4f,%.4f,%.4f,%zu,%.5f,%.5f,%.5f,%d,%u,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.3f\n",
                s.trial, s.step, static_cast<int>(s.guidance.mode), sc.transmitter.x(), sc.transmitter.y(),
                sc.transmitter.z(), sc.receiver.x(), sc.receiver.y(), sc.receiver.z(), sc.receiver_rpy.x(),
                sc.receiver_rpy.y(), sc.receiver_rpy.z(), s.measurement.field.x(), s.measurement.field.y(),
                s.measurement.field.z(), est.x(), est.y(), est.z(), s.guidance.uncertainty_radius_m, s.filter.size(),
                a.mass_within_45deg, a.mean_cosine, heading_cos, static_cast<int>(s.estimate.status),
                static_cast<unsigned>(s.measurement.valid_axes), err.x(), err.y(), err.z(), std::sqrt(P(0, 0)),
                std::sqrt(P(1, 1)), std::sqrt(P(2, 2)), nees);
  rows_.at(s.trial) += line;
}

void TraceCsv::write(std::ostream& out) const {
  out << header();
  for (const std::string& r : rows_) out << r;
}

}  // namespace sarloc::eval
