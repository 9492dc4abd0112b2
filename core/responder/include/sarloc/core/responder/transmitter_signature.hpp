#pragma once
// A transmitter as a receiver identifies it: its carrier offset from 457 kHz and its pulse
// period (EN 300 718: within +-80 Hz and 1000 +- 300 ms, each fixed by the transmitter's
// crystal). Every receiver measures them against its own oscillator, so each sigma states the
// measurement AND that receiver's oscillator tolerance: two receivers' signatures of one
// transmitter then differ by no more than their sigmas say. Incident command compares them
// across rescuers (incident/victim_fusion.hpp): two signals whose signatures differ are two
// transmitters, however close their estimates; two FOUNDs whose signatures agree may be one.
#include <optional>
#include <string>

namespace sarloc::responder {

struct TransmitterSignature {
  double carrier_offset_hz = 0.0;
  double carrier_sigma_hz = 0.0;  ///< 1 sigma; 0: the carrier is not known
  double period_s = 0.0;
  double period_sigma_s = 0.0;    ///< 1 sigma; 0: the period is not known

  bool carrier_known() const { return carrier_sigma_hz > 0.0; }
  bool period_known() const { return period_sigma_s > 0.0; }
  bool known() const { return carrier_known() || period_known(); }
};

/// Throws InputError naming `where`.<field> for a non-finite value, a negative sigma, a carrier
/// beyond +-1000 Hz or a period beyond [0, 10] s (nothing a receiver can have measured).
void check_signature(const TransmitterSignature& s, const std::string& where);

/// What two signatures say about their transmitters.
enum class SignatureMatch : unsigned char {
  kUnknown,   ///< they share no known component: nothing said
  kDistinct,  ///< a component differs beyond the gate: two transmitters
  kAlike,     ///< every component both know agrees within the gate (one, or two alike)
};

/// Compares the components both know: d^2 = sum (difference / combined sigma)^2 against
/// chi2_k(gate_probability), k = 1 or 2 components. kAlike needs both components known on
/// both sides when `need_both` (a carrier alone is shared by many transmitters).
SignatureMatch compare_signatures(const TransmitterSignature& a, const TransmitterSignature& b,
                                  double gate_probability, bool need_both = false);

}  // namespace sarloc::responder
