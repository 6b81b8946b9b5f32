#pragma once
// The benchmark figure of the dynamic filter's evidence: per cue, how far its
// measure went on keypoints of the static scene and on walking people
// (report.json's mask_scores.measure_histograms). Recall and false rejection
// say how well the cues did together; this shows which cue separates the two
// classes and where along its measure, i.e. where a threshold would cut.
#include <opencv2/core.hpp>

#include <optional>
#include <string>
#include <vector>

#include "bench/plot_area.h"

namespace dynslam {

/// One cue's histograms over its measure (1 = just passed the cue's test):
/// bin b counts keypoints measuring [first + b * bin_width,
/// first + (b + 1) * bin_width); the last bin holds everything above.
struct CueHistogram {
  std::string cue;  ///< report.json key ("box", "dense_flow", ...)
  std::vector<double> static_counts, walker_counts;
};

struct CueEvidence {
  double first = 1.0, bin_width = 0.25;
  std::vector<CueHistogram> cues;  ///< the cues that measured any keypoint, in the filter's order
};

/// The histograms in a report.json's text, of the cues that measured any
/// keypoint; nullopt when it has no mask_scores.measure_histograms (a run
/// without true masks, or an older one) or no cue measured any (mode off).
std::optional<CueEvidence> readCueEvidence(const std::string& report_json);

/// Colours (BGR) of the static and walker bars.
inline const cv::Scalar kStaticBarColour(190, 120, 30);
inline const cv::Scalar kWalkerBarColour(30, 110, 235);

/// A grid of panels, one per graded cue that measured any keypoint, each
/// with the share of static and of walker keypoints per bin side by side;
/// the cues whose measure is always 1 get their counts in a line below.
class CueEvidencePlot {
 public:
  explicit CueEvidencePlot(CueEvidence evidence, cv::Size size = {1200, 800});
  cv::Mat render(const std::string& title) const;
  /// The data-to-pixel mapping of a cue's panel (x = measure, y = percent
  /// of the class's keypoints); nullptr when the cue has no panel.
  const PlotArea* areaOf(const std::string& cue) const;

 private:
  struct Panel {
    std::size_t cue;  ///< index into evidence_.cues
    PlotArea area;
  };
  CueEvidence evidence_;
  cv::Size size_;
  std::vector<Panel> panels_;
};

}  // namespace dynslam
