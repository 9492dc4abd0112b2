// Trials of the multiple-burial evaluation that once confirmed a victim where none is, run as
// sarloc-eval runs them (config/eval/avalanche.yaml): each must give no ghost, and each still
// gives one without the rule that fixed it, so the trial keeps testing what it was kept for.
// The rule here is the found witness (rescuer_search.found_witness_window_s, on by default):
// docs/estimation/avalanche.md, "Found witness", gives why.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "eval_config.hpp"
#include "sarloc/core/avalanche/multi_burial.hpp"

namespace sarloc::avalanche {
namespace {

// What `sarloc-eval multi-burial -c config/eval/avalanche.yaml --victims 4 --spread 5` sets up,
// with `simulation.receiver.oscillator_sigma_ppm: 0`, `search.confirm_max_waits: 10`,
// `simulation.receiver.two_tone_span_hz: 0`, `simulation.receiver.same_carrier_pairs: false` and
// `simulation.receiver.continuous_listening: false`, `simulation.receiver.calibration_relative:
// 0.015`, `sog.field_carrier_hz: 0`, `sog.calibration_gain_sigma: 0`,
// `sog.calibration_pointing_sigma_deg: 0` and `sog.initial_components: 1700`.
MultiBurialSetup four_within_five_metres(std::uint64_t seed) {
  EvaluationSetup base;
  eval::load_avalanche_config(std::string(SARLOC_SOURCE_DIR) + "/config/eval/avalanche.yaml", base);
  MultiBurialSetup setup = eval::multi_burial_setup(base, 4, 5.0, base.evaluation.trials);
  // Recorded before devices had an oscillator error (2026-11-29): its draw shifts every carrier a
  // device hears on the detector's grid, and the walk with it, so these trials would be others.
  setup.simulation.receiver.oscillator_sigma_ppm = 0.0;
  // ... and while a probe point was waited on 10 epochs at most (search.confirm_max_waits): the
  // longer waits change the walk, and without the witness seed 13 trial 2 then finds no ghost.
  setup.rescuer.search.confirm_max_waits = 10;
  // ... and before the detector split two tones starting together (two_tone_span_hz) or a pair in
  // lockstep (same_carrier_pairs): each changes which pulses the tracks hear, and with the first
  // both trials find no ghost even without the witness.
  setup.simulation.receiver.two_tone_span_hz = 0.0;
  setup.simulation.receiver.same_carrier_pairs = false;
  // ... and while the device's windows were cut apart (continuous_listening, issue 58).
  setup.simulation.receiver.continuous_listening = false;
  // ... and while the filter modelled the quasi-static field and the device stated its
  // calibration as white noise (2026-12-05): with the field at the carrier and the calibration
  // as consider parameters, neither trial finds a ghost even without the witness.
  setup.rescuer.sog = setup.rescuer.sog.quasi_static();
  setup.simulation.receiver.calibration_relative = 0.015;
  // ... and while every ring opened with seed 000's 1700 Gaussians (2026-12-06: 600 for a far
  // ring): fewer move every walk, and these trials would be others.
  setup.rescuer.sog.initial_components = 1700;
  // ... and before a confirmation asked how far the latest samples alone allow the victim
  // (search.confirm_window_reach_factor, 2026-12-08): it too changes when confirmations come.
  setup.rescuer.search.confirm_window_reach_factor = 0.0;
  setup.evaluation.seed = seed;
  setup.validate();
  return setup;
}

struct WithAndWithout {
  MultiBurialTrial with;     ///< the found witness on (30 s)
  MultiBurialTrial without;  ///< off
};

WithAndWithout run_with_and_without_witness(std::uint64_t seed, std::uint32_t trial) {
  MultiBurialSetup setup = four_within_five_metres(seed);
  setup.rescuer.found_witness_window_s = 30.0;
  WithAndWithout out;
  out.with = run_multi_burial_trial(setup, trial);
  setup.rescuer.found_witness_window_s = 0.0;
  out.without = run_multi_burial_trial(setup, trial);
  return out;
}

// Seed 14, trial 97 (docs/estimation/avalanche.md, "Found witness"): a signal followed victim 2's
// pulses, then, carriers 0.03 Hz apart and periods in lockstep, victim 3's, clean; its filter kept
// victim 2's moment and was FOUND 1.5 m from victim 3 with a 0.48 m radius. The witness, built
// from the last 30 s only, was 1.2 m away with a 1.16 m radius, more than twice the located
// radius: the FOUND waited, and the samples that followed decided.
// Seed 13, trial 2: a signal whose filter took a pulse of victims 0 and 3 summed (periods 3 ms
// apart, carriers 0.72 Hz, fields nearly parallel at the receiver: not flagged elliptical) was
// FOUND 0.86 m from victim 3 with a 0.17 m radius after victim 3's own clean pulses.
//
// Each trial reproduces bit for bit on one machine, but a walk of hundreds of steps follows the
// last bits of the floating point: on the Intel Xeon where they were traced both gave a ghost
// without the witness; on an AMD EPYC (2026-11-29) seed 13 trial 2 gives none, and its filter
// never asks for the witness. So every traced trial must be free of
// ghosts with the witness, and at least one of them must still give its ghost without it (and
// have the witness withdraw or defer a FOUND with it), or the test no longer tests the rule.
TEST(TracedTrials, TheFoundWitnessKeepsTheCarrierMateGhostsAway) {
  struct Traced {
    std::uint64_t seed;
    std::uint32_t trial;
    bool all_found;  ///< every victim FOUND with the witness on
  };
  int exercised = 0;
  for (const Traced t : {Traced{14, 97, true}, Traced{13, 2, false}}) {
    SCOPED_TRACE("seed " + std::to_string(t.seed) + " trial " + std::to_string(t.trial));
    const auto [with, without] = run_with_and_without_witness(t.seed, t.trial);
    EXPECT_EQ(with.ghosts, 0u);
    if (t.all_found) {
      EXPECT_TRUE(with.all_found);
    }
    if (without.ghosts == 0) continue;
    ++exercised;
    EXPECT_GE(with.withdrawn_founds + with.deferred_founds, 1u);
  }
  EXPECT_GE(exercised, 1) << "no traced trial exercises the failure the witness was built for";
}

// Seed 10, trial 67, as shipped (docs/estimation/avalanche.md, "What the latest samples say"):
// victim 3, the deepest of four (2.76 m), pulses in lockstep with victim 2; its signal's filter
// collapsed on a place 1.2 m north of it and 0.86 m too shallow, and was FOUND there with a
// 0.29 m radius while its last 11 samples allowed the victim 1.22 m from the estimate. With the
// window's reach asked of every confirmation the trial finds all four and no ghost; on main
// before it (8cd94e0, this Intel Xeon VM and the AMD EPYC one before) it gave that ghost. The
// run without the rule is not repeated here: it takes a minute, and a walk this long follows
// the floating point's last bits, so on another machine it may take another course.
TEST(TracedTrials, TheWindowsReachKeepsADeepVictimsCollapsedFilterFromAFound) {
  EvaluationSetup base;
  eval::load_avalanche_config(std::string(SARLOC_SOURCE_DIR) + "/config/eval/avalanche.yaml", base);
  MultiBurialSetup setup = eval::multi_burial_setup(base, 4, 5.0, base.evaluation.trials);
  setup.evaluation.seed = 10;
  setup.validate();
  const MultiBurialTrial trial = run_multi_burial_trial(setup, 67);
  EXPECT_EQ(trial.ghosts, 0u);
  EXPECT_TRUE(trial.all_found);
}

}  // namespace
}  // namespace sarloc::avalanche
