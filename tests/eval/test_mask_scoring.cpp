// Ground-truth scoring of per-keypoint dynamic flags against composite
// sequences' people masks: the per-frame counts (scoreKeypoints) on
// hand-made masks, and the run-level scorer that reads masks/<rgb stem>.png
// and writes report.json's "mask_scores".
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/json_writer.h"
#include "core/keypoint_labels.h"
#include "eval/keypoint_truth_scorer.h"
#include "eval/mask_scoring.h"
#include "testing/test_support.h"

using namespace dynslam;
using dynslam::test::TempDir;

TEST(MaskScoring, CountsAgainstAHandMadeMask) {
  // 40x20 mask: walker 1 at x 2..13, person 2 standing still (130) at
  // x 26..35, both rows 2..17; static in between (x 17..22 is >= 3 px from both).
  cv::Mat gt(20, 40, CV_8U, cv::Scalar(0));
  gt(cv::Rect(2, 2, 12, 16)).setTo(1);
  gt(cv::Rect(26, 2, 10, 16)).setTo(130);
  const std::vector<cv::Point2f> pts = {
      {7, 9},    // walker core (5 px from the nearest edge)  flagged     -> TP
      {8, 10},   // walker core                               not flagged -> miss
      {5, 5},    // walker, exactly 3 px inside: core         flagged     -> TP
      {3, 9},    // walker, 1 px inside: boundary             flagged
      {15, 9},   // static, 2 px from the walker: boundary
      {30, 10},  // standing core                             flagged
      {31, 9},   // standing core                             not flagged
      {19, 0},   // static                                    flagged     -> false rejection
      {20, 19},  // static                                    not flagged
      {24, 5},   // static, 2 px from the standing person: boundary
      {-1, 5},   // outside the image: skipped
  };
  const std::vector<uint8_t> flags = {1, 0, 1, 1, 0, 1, 0, 1, 0, 0, 1};
  const MaskScore s = scoreKeypoints(pts, flags, gt);
  EXPECT_EQ(s.walker_points, 3);
  EXPECT_EQ(s.walker_flagged, 2);
  EXPECT_EQ(s.standing_points, 2);
  EXPECT_EQ(s.standing_flagged, 1);
  EXPECT_EQ(s.static_points, 2);
  EXPECT_EQ(s.static_flagged, 1);
  EXPECT_EQ(s.boundary_points, 3);
  EXPECT_EQ(s.boundary_flagged, 1);
  EXPECT_DOUBLE_EQ(s.recall(), 2.0 / 3.0);
  EXPECT_DOUBLE_EQ(s.falseRejectionRate(), 0.5);
  EXPECT_DOUBLE_EQ(s.standingRejectionRate(), 0.5);

  MaskScore sum = s;
  sum += s;
  EXPECT_EQ(sum.walker_points, 6);
  EXPECT_DOUBLE_EQ(sum.recall(), 2.0 / 3.0);
  EXPECT_TRUE(std::isnan(MaskScore().recall()));
  EXPECT_THROW(scoreKeypoints(pts, {1, 0}, gt), std::invalid_argument);
}

// The dynamic stage's cues of the flagged points are counted per cue, and
// per sole motion cue: a walker point flagged by a region alone, one by a
// region and a box, a static point flagged by the dense flow alone (with a
// doubt cue beside it), an unflagged static point with a cue (not counted).
TEST(MaskScoring, FlaggedPointsCountedByCue) {
  cv::Mat gt(20, 40, CV_8U, cv::Scalar(0));
  gt(cv::Rect(2, 2, 12, 16)).setTo(1);
  const std::vector<cv::Point2f> pts = {{7, 9}, {8, 10}, {20, 5}, {20, 15}};
  const std::vector<uint8_t> flags = {1, 1, 1, 0};
  std::vector<CueMeasures> cues(4);
  cues[0].add(cue::kRegion, 2.f);
  cues[1].add(cue::kRegion, 1.1f);
  cues[1].add(cue::kBox, 3.f);
  cues[2].add(cue::kDenseFlow, 9.f);
  cues[2].add(cue::kMovedSpace);
  cues[3].add(cue::kBox, 1.f);
  const MaskScore s = scoreKeypoints(pts, flags, gt, 3, nullptr, 0.01, &cues);
  auto bit = [](uint16_t c) { return __builtin_ctz(c); };
  EXPECT_EQ(s.walker_flagged_by_cue[bit(cue::kRegion)], 2);
  EXPECT_EQ(s.walker_flagged_only_cue[bit(cue::kRegion)], 1);
  EXPECT_EQ(s.walker_flagged_by_cue[bit(cue::kBox)], 1);
  EXPECT_EQ(s.walker_flagged_only_cue[bit(cue::kBox)], 0);
  EXPECT_EQ(s.static_flagged_by_cue[bit(cue::kDenseFlow)], 1);
  EXPECT_EQ(s.static_flagged_only_cue[bit(cue::kDenseFlow)], 1);
  EXPECT_EQ(s.static_flagged_by_cue[bit(cue::kMovedSpace)], 1);
  EXPECT_EQ(s.static_flagged_by_cue[bit(cue::kBox)], 0) << "not flagged: not counted";
  // Each cue's measure is binned, flagged or not: [1 + b/4, 1 + (b+1)/4),
  // the last bin everything above.
  EXPECT_EQ(s.walker_measures[bit(cue::kRegion)][4], 1);  // 2.0
  EXPECT_EQ(s.walker_measures[bit(cue::kRegion)][0], 1);  // 1.1
  EXPECT_EQ(s.walker_measures[bit(cue::kBox)][8], 1);     // 3.0
  EXPECT_EQ(s.static_measures[bit(cue::kDenseFlow)][MaskScore::kMeasureBins - 1], 1);  // 9
  EXPECT_EQ(s.static_measures[bit(cue::kBox)][0], 1) << "unflagged points count too";
  EXPECT_EQ(s.static_measures[bit(cue::kRegion)][0], 0);
  const std::vector<CueMeasures> short_cues(1);
  EXPECT_THROW(scoreKeypoints(pts, flags, gt, 3, nullptr, 0.01, &short_cues),
               std::invalid_argument);
}

TEST(MaskScoringBoxes, StaticPointsInUnmaskedPersonBoxesCountedApart) {
  cv::Mat gt(100, 200, CV_8U, cv::Scalar(0));
  gt(cv::Rect(20, 20, 30, 60)).setTo(1);  // a walker
  // Points: 2 on the walker, 2 static inside a box on nobody (the seated
  // person), 2 static elsewhere; flags: walker both, seated both, other one.
  const std::vector<cv::Point2f> pts = {{35, 50},  {30, 40},  {130, 50},
                                        {140, 60}, {180, 10}, {100, 90}};
  const std::vector<uint8_t> flags = {1, 1, 1, 1, 1, 0};
  const std::vector<cv::Rect2f> boxes = {cv::Rect2f(120, 30, 40, 50),  // on nobody
                                         cv::Rect2f(15, 15, 40, 70)};  // on the walker
  const MaskScore s = scoreKeypoints(pts, flags, gt, 3, &boxes);
  EXPECT_EQ(s.walker_points, 2);
  EXPECT_EQ(s.static_points, 4);
  EXPECT_EQ(s.static_flagged, 3);
  EXPECT_EQ(s.static_in_unmasked_box, 2);
  EXPECT_EQ(s.static_in_unmasked_box_flagged, 2);
  EXPECT_DOUBLE_EQ(s.falseRejectionRate(), 0.75);
  EXPECT_DOUBLE_EQ(s.falseRejectionRateOutsideUnmaskedBoxes(), 0.5);
  // Without boxes nothing is set apart.
  const MaskScore n = scoreKeypoints(pts, flags, gt, 3);
  EXPECT_EQ(n.static_in_unmasked_box, 0);
  EXPECT_DOUBLE_EQ(n.falseRejectionRateOutsideUnmaskedBoxes(), 0.75);
}

TEST(MaskScoringBoxes, BadInputsThrow) {
  const cv::Mat gt(10, 10, CV_8U, cv::Scalar(0));
  EXPECT_THROW(scoreKeypoints({{1, 1}}, {}, gt), std::invalid_argument);
  EXPECT_THROW(scoreKeypoints({{1, 1}}, {0}, cv::Mat(10, 10, CV_16U)), std::invalid_argument);
  EXPECT_THROW(scoreKeypoints({{1, 1}}, {0}, cv::Mat()), std::invalid_argument);
  EXPECT_THROW(scoreKeypoints({{1, 1}}, {0}, gt, -1), std::invalid_argument);
}

namespace {

/// 40x20 mask: walker 1 at x 2..13, rows 2..17; static elsewhere.
cv::Mat walkerMask() {
  cv::Mat gt(20, 40, CV_8U, cv::Scalar(0));
  gt(cv::Rect(2, 2, 12, 16)).setTo(1);
  return gt;
}

}  // namespace

// Two frames of a composite sequence: the counts are the sums of the
// frames' hand-counted scores; tracking's flags (before the revision) are
// scored apart, and a frame without them counts its final flags there.
TEST(KeypointTruthScorer, SumsFramesAndScoresTrackingsFlagsApart) {
  TempDir d;
  makeDirectories(d / "seq/masks");
  ASSERT_TRUE(cv::imwrite(d / "seq/masks/1305031102.175304.png", walkerMask()));
  ASSERT_TRUE(cv::imwrite(d / "seq/masks/1305031102.211214.png", walkerMask()));
  std::optional<KeypointTruthScorer> scorer = KeypointTruthScorer::forSequence(d / "seq");
  ASSERT_TRUE(scorer);
  EXPECT_EQ(scorer->masksDir(), d / "seq/masks");

  // Walker core (7,9) and (8,10); static (25,9) and (30,15).
  const std::vector<cv::Point2f> pts = {{7, 9}, {8, 10}, {25, 9}, {30, 15}};
  scorer->addFrame("rgb/1305031102.175304.png", {40, 20}, pts, {1, 0, 1, 0}, {0, 0, 1, 1}, {});
  scorer->addFrame("/abs/rgb/1305031102.211214.png", {40, 20}, pts, {1, 1, 0, 0}, {}, {});
  ASSERT_EQ(scorer->frames().size(), 2u);
  EXPECT_EQ(scorer->frames()[0].walker_flagged, 1);
  EXPECT_EQ(scorer->frames()[0].static_flagged, 1);
  EXPECT_EQ(scorer->frames()[1].walker_flagged, 2);
  EXPECT_EQ(scorer->frames()[1].static_flagged, 0);
  EXPECT_EQ(scorer->total().walker_points, 4);
  EXPECT_EQ(scorer->total().walker_flagged, 3);
  EXPECT_EQ(scorer->total().static_points, 4);
  EXPECT_EQ(scorer->total().static_flagged, 1);
  EXPECT_DOUBLE_EQ(scorer->total().recall(), 0.75);
  EXPECT_DOUBLE_EQ(scorer->total().falseRejectionRate(), 0.25);
  // Before tracking: frame 1 {0,0,1,1} (no walker, 2 static flagged),
  // frame 2 its final flags (2 walkers).
  EXPECT_DOUBLE_EQ(scorer->beforeTracking().recall(), 0.5);
  EXPECT_DOUBLE_EQ(scorer->beforeTracking().falseRejectionRate(), 0.5);

  JsonWriter w;
  w.beginObject();
  scorer->writeJson(w);
  w.endObject();
  const std::string json = w.str();
  for (const char* member :
       {"\"frames_scored\": 2", "\"walker_points\": 4", "\"walker_flagged\": 3", "\"recall\": 0.75",
        "\"static_points\": 4", "\"false_rejection_rate\": 0.25",
        "\"standing_rejection_rate\": null", "\"before_tracking\": {", "\"recall\": 0.5",
        "\"false_rejection_rate\": 0.5"})
    EXPECT_NE(json.find(member), std::string::npos) << member << " in " << json;
  // Per frame: walker points, flagged, static points, flagged.
  auto compact = json;
  compact.erase(std::remove_if(compact.begin(), compact.end(), ::isspace), compact.end());
  EXPECT_NE(compact.find(
                "\"per_frame_walker_points_flagged_static_points_flagged\":[[2,1,2,1],[2,2,2,0]]"),
            std::string::npos)
      << json;
}

TEST(KeypointTruthScorer, NoMasksFolderNoScorer) {
  TempDir d;
  makeDirectories(d / "seq/rgb");
  EXPECT_FALSE(KeypointTruthScorer::forSequence(d / "seq"));
  EXPECT_FALSE(KeypointTruthScorer::forSequence(d / "seq.rawlog"));
}

TEST(KeypointTruthScorer, MissingOrWrongMaskNamesTheFile) {
  TempDir d;
  makeDirectories(d / "masks");
  KeypointTruthScorer scorer(d / "masks");
  try {
    scorer.addFrame("rgb/1.000000.png", {40, 20}, {}, {}, {}, {});
    ADD_FAILURE() << "no exception";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), d / "masks/1.000000.png");
  }
  ASSERT_TRUE(cv::imwrite(d / "masks/2.png", walkerMask()));
  try {
    scorer.addFrame("rgb/2.png", {640, 480}, {}, {}, {}, {});  // not the RGB image's size
    ADD_FAILURE() << "no exception";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), d / "masks/2.png");
  }
  ASSERT_TRUE(cv::imwrite(d / "masks/3.png", cv::Mat(20, 40, CV_8UC3, cv::Scalar(0, 0, 0))));
  EXPECT_THROW(scorer.addFrame("3.png", {40, 20}, {}, {}, {}, {}), InputError);
  EXPECT_TRUE(scorer.frames().empty());
}
