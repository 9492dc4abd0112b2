#pragma once
// Seeded mutations of valid inputs for the dashboard's fuzz tests: 1-5 edits each, a byte
// flipped, inserted or cut, a piece repeated, a run of the format's own punctuation inserted, or
// the rest cut off. The same seed gives the same cases on every machine.
#include <cstdint>
#include <cstdlib>
#include <random>
#include <string>

namespace sarloc::dashboard::test {

/// The number of fuzz cases: 10 000 in CI (under 60 s for both fuzz tests), more for a longer
/// documented run with SARLOC_FUZZ_CASES=N (docs/operations/dashboard.md).
inline int fuzz_cases() {
  const char* wanted = std::getenv("SARLOC_FUZZ_CASES");
  const int n = wanted != nullptr ? std::atoi(wanted) : 0;
  return n >= 100 ? n : 10000;
}

class Mutator {
 public:
  /// `punctuation`: the characters that give the format its structure ("{}[]:," for JSON).
  Mutator(std::uint32_t seed, std::string punctuation) : rng_(seed), punctuation_(std::move(punctuation)) {}

  std::string operator()(std::string text) {
    const int edits = 1 + static_cast<int>(rng_() % 5);
    for (int e = 0; e < edits; ++e) {
      const std::size_t at = text.empty() ? 0 : rng_() % text.size();
      switch (rng_() % 7) {
        case 0: if (!text.empty()) text[at] = static_cast<char>(rng_() % 256); break;
        case 1: text.insert(at, 1, static_cast<char>(rng_() % 256)); break;
        case 2: text.erase(at, rng_() % 16); break;
        case 3: text.insert(at, text.substr(at, rng_() % 64)); break;
        case 4: {
          std::string run(rng_() % 300, ' ');
          for (auto& c : run) c = punctuation_[rng_() % punctuation_.size()];
          text.insert(at, run);
          break;
        }
        case 5: text.insert(at, std::to_string(rng_())); break;
        default: text = text.substr(0, at); break;
      }
    }
    return text;
  }
  /// The generator itself, for the test's other seeded choices.
  std::mt19937& rng() { return rng_; }

 private:
  std::mt19937 rng_;
  std::string punctuation_;
};

}  // namespace sarloc::dashboard::test
