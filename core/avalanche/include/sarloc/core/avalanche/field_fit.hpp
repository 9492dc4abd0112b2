#pragma once
// How well one field sample fits a signal's filter, asked without updating it: the receiver's
// separation (signal_separator.hpp) compares tracks with it when carrier and timing cannot
// decide, and refuses to re-anchor a lost track on a pulse its filter cannot explain.

#include <cstdint>

namespace sarloc::avalanche {

struct FieldFit {
  /// log p(field | the filter's belief), up to a constant common to every filter: compare
  /// filters with it, never with a threshold.
  double log_likelihood = 0.0;
  /// Normalised innovation squared of the component that explains the field best, sign
  /// included (chi-square with one degree of freedom per valid axis if the filter is right).
  double nis = 0.0;
  /// Non-zero: this signal's filter is a suspected repeat of that signal's, the same transmitter
  /// by position and moment (same_transmitter.hpp). Of several lost tracks on a pulse's
  /// carrier, the separation re-anchors the one that is no repeat of another, rather than none
  /// (SignalSeparator::original_of_repeats).
  std::uint32_t repeat_of = 0;
};

}  // namespace sarloc::avalanche
