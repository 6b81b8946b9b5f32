// nearestTracks on hand-placed tracks and keypoints whose nearest track is
// known.
#include <gtest/gtest.h>

#include <vector>

#include "dynamic/track_neighbours.h"

using namespace dynslam;

namespace {

std::vector<cv::KeyPoint> keysAt(const std::vector<cv::Point2f>& at) {
  std::vector<cv::KeyPoint> k;
  for (const auto& p : at) k.emplace_back(p, 7.f);
  return k;
}

const cv::Size kImage(320, 240);

}  // namespace

TEST(TrackNeighbours, TheNearestJudgedTrackIsFound) {
  // Tracks: 0 at (100, 100), 1 at (112, 100), 2 not tracked at (106, 104),
  // 3 at (300, 20).
  const std::vector<cv::Point2f> tracks = {{100, 100}, {112, 100}, {106, 104}, {300, 20}};
  const std::vector<uint8_t> tracked = {1, 1, 0, 1};
  const auto keys = keysAt({
      {103, 100},  // 3 px from track 0, 9 from track 1
      {109, 101},  // nearer track 1; the untracked one does not count
      {100, 112},  // 12 px from track 0: within the radius of 15
      {112, 116},  // 16 px from track 1: none near
      {290, 25},   // beside the lone track 3
      {10, 230},   // far from everything
  });
  EXPECT_EQ(nearestTracks(keys, tracks, tracked, kImage, 15.0),
            (std::vector<int>{0, 1, 0, -1, 3, -1}));
}

TEST(TrackNeighbours, TiesGoToTheLowerIndexAndTheRadiusIsExclusive) {
  // A keypoint halfway between two tracks.
  const std::vector<cv::Point2f> tracks = {{50, 50}, {70, 50}};
  const auto keys = keysAt({{60, 50}, {60, 60.5f}});
  EXPECT_EQ(nearestTracks(keys, tracks, {1, 1}, kImage, 20.0), (std::vector<int>{0, 0}));
  EXPECT_EQ(nearestTracks(keys, tracks, {0, 1}, kImage, 20.0), (std::vector<int>{1, 1}));
  // Exactly at the radius (10 px) is not near.
  EXPECT_EQ(nearestTracks(keysAt({{60, 50}}), tracks, {1, 1}, kImage, 10.0),
            (std::vector<int>{-1}));
}

TEST(TrackNeighbours, TracksAcrossBucketsAndOutsideTheImageAreFound) {
  // Buckets are `radius` wide: a track in the next bucket, and one just
  // outside the image, are still the nearest.
  const std::vector<cv::Point2f> tracks = {{29.5f, 10}, {-3, 200}, {1e9f, -1e9f}};
  const auto keys = keysAt({{31, 10}, {2, 200}});
  EXPECT_EQ(nearestTracks(keys, tracks, {1, 1, 1}, kImage, 30.0), (std::vector<int>{0, 1}));
}

TEST(TrackNeighbours, NoTracksOrNoRadiusFindNothing) {
  const auto keys = keysAt({{10, 10}, {200, 100}});
  EXPECT_EQ(nearestTracks(keys, {}, {}, kImage, 30.0), (std::vector<int>{-1, -1}));
  EXPECT_EQ(nearestTracks(keys, {{10, 10}}, {1}, kImage, 0.0), (std::vector<int>{-1, -1}));
}
