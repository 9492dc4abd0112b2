// Pairing a track's strides with a footprint truth's when the stance detector missed or split a
// footfall, and under a heading drift that turns every stride a little more.
#include "sarloc/core/firefighter/stride_matching.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "sarloc/core/common/angle.hpp"

namespace sarloc::firefighter {
namespace {

// A walk of 1.3 m strides with a right-angle turn every `leg` strides, split over two strides.
std::vector<Eigen::Vector2d> truth_strides(int count, int leg) {
  std::vector<Eigen::Vector2d> s;
  double heading = 0.0;
  for (int k = 0; k < count; ++k) {
    if (k % leg == leg - 2 || k % leg == leg - 1) heading += kPi / 4.0;
    s.push_back(1.3 * Eigen::Vector2d(std::cos(heading), std::sin(heading)));
  }
  return s;
}

// The track as an INS sees it: turned by a drift of 0.5 degree per stride.
std::vector<Eigen::Vector2d> drifted(const std::vector<Eigen::Vector2d>& strides) {
  std::vector<Eigen::Vector2d> out;
  for (std::size_t k = 0; k < strides.size(); ++k)
    out.push_back(Eigen::Rotation2Dd(0.5 * kDeg * static_cast<double>(k)) * strides[k]);
  return out;
}

TEST(StrideMatching, PairsOneForOneWhenEveryFootfallWasFound) {
  const auto truth = truth_strides(30, 8);
  const auto pairs = match_strides(drifted(truth), truth);
  ASSERT_EQ(pairs.size(), 30u);
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    EXPECT_EQ(pairs[k].track_begin, k);
    EXPECT_EQ(pairs[k].truth_begin, k);
    EXPECT_EQ(pairs[k].truth_end, k + 1);
  }
}

TEST(StrideMatching, GroupsAMissedFootfallAndASplitOneAndKeepsThePairsAfterThemRight) {
  const auto truth = truth_strides(30, 8);
  std::vector<Eigen::Vector2d> track;
  for (std::size_t k = 0; k < truth.size(); ++k) {
    if (k == 6) {  // footfall 7 missed: one stride across two
      track.push_back(truth[6] + truth[7]);
      ++k;
    } else if (k == 20) {  // stance 21 split mid-stride: two halves
      track.push_back(0.5 * truth[20]);
      track.push_back(0.5 * truth[20]);
    } else {
      track.push_back(truth[k]);
    }
  }
  const auto pairs = match_strides(drifted(track), truth);
  ASSERT_EQ(pairs.size(), 29u);
  const StridePair& missed = pairs[6];
  EXPECT_EQ(missed.track_end - missed.track_begin, 1u);
  EXPECT_EQ(missed.truth_begin, 6u);
  EXPECT_EQ(missed.truth_end, 8u);
  const StridePair& split = pairs[19];
  EXPECT_EQ(split.track_end - split.track_begin, 2u);
  EXPECT_EQ(split.truth_begin, 20u);
  EXPECT_EQ(split.truth_end, 21u);
  EXPECT_EQ(pairs.back().truth_end, 30u);
  EXPECT_EQ(pairs.back().track_end, track.size());
}

TEST(StrideMatching, StopsWhereTheShorterSequenceEnds) {
  const auto truth = truth_strides(30, 8);
  const std::vector<Eigen::Vector2d> track(truth.begin(), truth.begin() + 20);
  const auto pairs = match_strides(track, truth);
  ASSERT_EQ(pairs.size(), 20u);
  EXPECT_EQ(pairs.back().truth_end, 20u);
  EXPECT_TRUE(match_strides({}, truth).empty());
}

}  // namespace
}  // namespace sarloc::firefighter
