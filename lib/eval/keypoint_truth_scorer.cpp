#include "eval/keypoint_truth_scorer.h"

#include "core/atomic_file.h"
#include "core/keypoint_labels.h"
#include "core/truth_masks.h"

namespace dynslam {

std::optional<KeypointTruthScorer> KeypointTruthScorer::forSequence(const std::string& input) {
  if (!isDirectory(input + "/masks")) return std::nullopt;
  return KeypointTruthScorer(input + "/masks");
}

void KeypointTruthScorer::addFrame(const std::string& rgb_source, cv::Size image_size,
                                   const std::vector<cv::Point2f>& points,
                                   const std::vector<uint8_t>& flags,
                                   const std::vector<uint8_t>& flags_before_tracking,
                                   const std::vector<cv::Rect2f>& person_boxes,
                                   const std::vector<CueMeasures>& cues) {
  const cv::Mat gt = loadTruthMask(truthMaskPath(masks_dir_, rgb_source), image_size);
  frames_.push_back(scoreKeypoints(points, flags, gt, kMarginPx, &person_boxes, 0.01,
                                   cues.empty() ? nullptr : &cues));
  total_ += frames_.back();
  before_tracking_ += flags_before_tracking.empty() ? frames_.back()
                                                    : scoreKeypoints(points, flags_before_tracking,
                                                                     gt, kMarginPx, &person_boxes);
}

void KeypointTruthScorer::writeJson(JsonWriter& w) const {
  // Keypoints at least 3 px inside a walker / outside every person.
  w.beginObject("mask_scores")
      .value("masks", masks_dir_)
      .value("frames_scored", frames_.size())
      .value("walker_points", total_.walker_points)
      .value("walker_flagged", total_.walker_flagged)
      .value("recall", total_.recall())
      .value("static_points", total_.static_points)
      .value("static_flagged", total_.static_flagged)
      .value("false_rejection_rate", total_.falseRejectionRate())
      // Without the static points inside detected person boxes that overlap
      // no composite person (the real seated person, absent from the masks).
      .value("static_points_in_unmasked_person_boxes", total_.static_in_unmasked_box)
      .value("static_flagged_in_unmasked_person_boxes", total_.static_in_unmasked_box_flagged)
      .value("false_rejection_rate_outside_unmasked_person_boxes",
             total_.falseRejectionRateOutsideUnmaskedBoxes())
      .value("standing_points", total_.standing_points)
      .value("standing_flagged", total_.standing_flagged)
      .value("standing_rejection_rate", total_.standingRejectionRate());
  // Per cue: the flagged static and walker keypoints it was seen at, and
  // those it was the only motion cue at.
  w.beginObject("flagged_by_cue");
  for (int b = 0; b < cue::kCount; ++b)
    w.beginObject(cue::name(b))
        .value("static", total_.static_flagged_by_cue[b])
        .value("static_only", total_.static_flagged_only_cue[b])
        .value("walker", total_.walker_flagged_by_cue[b])
        .value("walker_only", total_.walker_flagged_only_cue[b])
        .endObject();
  w.endObject();
  // Per cue: how far its evidence went (CueMeasures) on the static and the
  // walker keypoints it was seen at, flagged or not.
  w.beginObject("measure_histograms")
      .value("first", 1.0)
      .value("bin_width", MaskScore::kMeasureBinWidth)
      .value("last_bin", "everything above");
  for (int b = 0; b < cue::kCount; ++b) {
    w.beginObject(cue::name(b));
    for (const auto& [name, h] : {std::pair{"static", &total_.static_measures[std::size_t(b)]},
                                  std::pair{"walker", &total_.walker_measures[std::size_t(b)]}}) {
      w.beginArray(name);
      for (int n : *h) w.element(n);
      w.endArray();
    }
    w.endObject();
  }
  w.endObject();
  // The scores above are of the final flags (what mapping uses); tracking
  // used these, before the frames the tracker's pose revised.
  w.beginObject("before_tracking")
      .value("recall", before_tracking_.recall())
      .value("false_rejection_rate", before_tracking_.falseRejectionRate())
      .value("false_rejection_rate_outside_unmasked_person_boxes",
             before_tracking_.falseRejectionRateOutsideUnmaskedBoxes())
      .endObject();
  w.beginArray("per_frame_walker_points_flagged_static_points_flagged");
  for (const MaskScore& m : frames_) {
    w.beginArray()
        .element(m.walker_points)
        .element(m.walker_flagged)
        .element(m.static_points)
        .element(m.static_flagged)
        .endArray();
  }
  w.endArray().endObject();
}

}  // namespace dynslam
