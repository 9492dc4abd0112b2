#include "sarloc/core/responder/transmitter_signature.hpp"

#include <cmath>

#include "sarloc/core/common/chi_square.hpp"
#include "sarloc/core/common/errors.hpp"

namespace sarloc::responder {
namespace {

void fail(const std::string& where, const char* field, double value, const char* rule) {
  throw InputError(where + "." + field + " = " + std::to_string(value) + ": " + rule);
}

}  // namespace

void check_signature(const TransmitterSignature& s, const std::string& where) {
  if (!std::isfinite(s.carrier_offset_hz) || std::fabs(s.carrier_offset_hz) > 1000.0)
    fail(where, "carrier_offset_hz", s.carrier_offset_hz, "must be finite and within +-1000 Hz");
  if (!std::isfinite(s.carrier_sigma_hz) || s.carrier_sigma_hz < 0.0 || s.carrier_sigma_hz > 1000.0)
    fail(where, "carrier_sigma_hz", s.carrier_sigma_hz, "must be in [0, 1000] (0: unknown)");
  if (!std::isfinite(s.period_s) || s.period_s < 0.0 || s.period_s > 10.0)
    fail(where, "period_s", s.period_s, "must be in [0, 10] s");
  if (!std::isfinite(s.period_sigma_s) || s.period_sigma_s < 0.0 || s.period_sigma_s > 10.0)
    fail(where, "period_sigma_s", s.period_sigma_s, "must be in [0, 10] s (0: unknown)");
}

SignatureMatch compare_signatures(const TransmitterSignature& a, const TransmitterSignature& b,
                                  double gate_probability, bool need_both) {
  double d2 = 0.0;
  int components = 0;
  if (a.carrier_known() && b.carrier_known()) {
    const double diff = a.carrier_offset_hz - b.carrier_offset_hz;
    d2 += diff * diff / (a.carrier_sigma_hz * a.carrier_sigma_hz + b.carrier_sigma_hz * b.carrier_sigma_hz);
    ++components;
  }
  if (a.period_known() && b.period_known()) {
    const double diff = a.period_s - b.period_s;
    d2 += diff * diff / (a.period_sigma_s * a.period_sigma_s + b.period_sigma_s * b.period_sigma_s);
    ++components;
  }
  if (components == 0) return SignatureMatch::kUnknown;
  if (d2 > chi_square_quantile(gate_probability, components)) return SignatureMatch::kDistinct;
  return need_both && components < 2 ? SignatureMatch::kUnknown : SignatureMatch::kAlike;
}

}  // namespace sarloc::responder
