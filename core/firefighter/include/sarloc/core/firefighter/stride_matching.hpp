#pragma once
// Which strides of a track are which strides of a footprint truth, when the stance detector
// missed a footfall or split one: a monotone alignment (dynamic programming) of the two stride
// sequences by what a heading drift does not change, each stride's length and its turn from the
// stride before. A group may pair one stride with one, two of the track with one of the truth (a
// split stance) or one with two (a missed one); strides of either left over at the end are not
// compared. Used by footprint_errors for the stride consistency (ins_recording.hpp).
//
//   for (const StridePair& p : match_strides(track_strides, truth_strides)) ...
#include <Eigen/Core>
#include <cstddef>
#include <vector>

namespace sarloc::firefighter {

/// Track strides [track_begin, track_end) paired with truth strides [truth_begin, truth_end).
struct StridePair {
  std::size_t track_begin = 0, track_end = 0, truth_begin = 0, truth_end = 0;
};

std::vector<StridePair> match_strides(const std::vector<Eigen::Vector2d>& track,
                                      const std::vector<Eigen::Vector2d>& truth);

}  // namespace sarloc::firefighter
