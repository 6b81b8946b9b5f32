// lib/bench/evidence_plots: report.json's cue histograms read back, their
// bars drawn in the bins they count, and `writeBenchPlots` drawing the figure
// only for a report that has them.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "bench/bench_plots.h"
#include "bench/evidence_plots.h"
#include "testing/test_support.h"

namespace dynslam {
namespace {

using test::TempDir;

constexpr int kBins = 29;

/// A histogram of kBins with `count` keypoints in bin `bin` (none if bin < 0).
std::string bins(int bin, int count) {
  std::ostringstream s;
  s << "[";
  for (int b = 0; b < kBins; ++b) s << (b ? ", " : "") << (b == bin ? count : 0);
  return s.str() + "]";
}

std::string cue(const char* name, int static_bin, int static_n, int walker_bin, int walker_n) {
  return std::string("\"") + name + "\": {\"static\": " + bins(static_bin, static_n) +
         ", \"walker\": " + bins(walker_bin, walker_n) + "}";
}

/// box: every static keypoint in bin 0 (1.00-1.25), every walker one in bin 8
/// (3.00-3.25); map_inlier the other way round, in the last bin and bin 4;
/// region all zero; covered_track (always 1) 7 static and 3 walkers.
/// flagged_by_cue repeats the cue keys with numbers, off the path.
std::string reportWithHistograms() {
  return R"({"fps": 30, "mask_scores": {"recall": 0.9,
    "flagged_by_cue": {"box": {"static": 3, "walker": 4}},
    "measure_histograms": {"first": 1.0, "bin_width": 0.25, "last_bin": "everything above", )" +
         cue("box", 0, 40, 8, 12) + ", " + cue("region", -1, 0, -1, 0) + ", " +
         cue("covered_track", 0, 7, 0, 3) + ", " + cue("map_inlier", kBins - 1, 5, 4, 9) +
         "}}, \"keyframes\": 4}";
}

void writeFile(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

/// Columns of `row` inside the panel painted exactly `colour`.
std::vector<int> columnsOf(const cv::Mat& img, const cv::Rect& panel, int row,
                           const cv::Scalar& colour) {
  const cv::Vec3b c{uchar(colour[0]), uchar(colour[1]), uchar(colour[2])};
  std::vector<int> cols;
  for (int x = panel.x; x < panel.x + panel.width; ++x)
    if (img.at<cv::Vec3b>(row, x) == c) cols.push_back(x);
  return cols;
}

/// Every column painted `colour` just above the panel's x axis lies in bin
/// [lo, lo + 0.25) of the measure, and there is one.
void expectBarIn(const cv::Mat& img, const PlotArea& a, const cv::Scalar& colour, double lo,
                 const std::string& what) {
  const int row = a.pixels().y + a.pixels().height - 4;
  const std::vector<int> cols = columnsOf(img, a.pixels(), row, colour);
  ASSERT_FALSE(cols.empty()) << what;
  EXPECT_GE(cols.front(), a.toPixel(lo, 0).x) << what;
  EXPECT_LE(cols.back(), a.toPixel(lo + 0.25, 0).x) << what;
  // Normalised to the class: one bin holding all of it reaches 100 %.
  int top = row;
  while (top > 0 &&
         img.at<cv::Vec3b>(top - 1, cols.front()) == img.at<cv::Vec3b>(row, cols.front()))
    --top;
  EXPECT_NEAR(top, a.toPixel(0, 100).y, 2) << what;
}

TEST(CueEvidence, ReadsTheHistogramsOfEveryCueTheReportHas) {
  const auto e = readCueEvidence(reportWithHistograms());
  ASSERT_TRUE(e);
  EXPECT_DOUBLE_EQ(e->first, 1.0);
  EXPECT_DOUBLE_EQ(e->bin_width, 0.25);
  ASSERT_EQ(e->cues.size(), 3u);  // in the filter's order, absent and all-zero cues left out
  EXPECT_EQ(e->cues[0].cue, "box");
  EXPECT_EQ(e->cues[2].cue, "map_inlier");
  ASSERT_EQ(e->cues[0].static_counts.size(), std::size_t(kBins));
  EXPECT_EQ(e->cues[0].static_counts[0], 40);
  EXPECT_EQ(e->cues[0].walker_counts[8], 12);
  EXPECT_EQ(e->cues[2].static_counts[kBins - 1], 5);
  EXPECT_FALSE(readCueEvidence(R"({"fps": 30, "mask_scores": {"recall": 0.9}})"));
  // A run whose dynamic stage was off measured nothing: no figure.
  EXPECT_FALSE(readCueEvidence(
      R"({"mask_scores": {"measure_histograms": {"first": 1.0, "bin_width": 0.25, )" +
      cue("box", -1, 0, -1, 0) + ", " + cue("region", -1, 0, -1, 0) + "}}}"));
  EXPECT_FALSE(readCueEvidence("{}"));
}

TEST(CueEvidence, BarsStandInTheBinsTheyCount) {
  const CueEvidencePlot plot(*readCueEvidence(reportWithHistograms()), {1200, 800});
  const cv::Mat img = plot.render("seq, detect+flow, run 1: cue measures");
  EXPECT_EQ(img.size(), cv::Size(1200, 800));
  EXPECT_EQ(plot.areaOf("region"), nullptr);         // all zero
  EXPECT_EQ(plot.areaOf("covered_track"), nullptr);  // always 1: a line of text
  const PlotArea* box = plot.areaOf("box");
  const PlotArea* inlier = plot.areaOf("map_inlier");
  ASSERT_TRUE(box && inlier);
  EXPECT_DOUBLE_EQ(box->x0(), 1.0);
  EXPECT_DOUBLE_EQ(box->x1(), 8.25);
  EXPECT_LT(box->pixels().x + box->pixels().width, inlier->pixels().x);  // side by side
  expectBarIn(img, *box, kStaticBarColour, 1.0, "box static");
  expectBarIn(img, *box, kWalkerBarColour, 3.0, "box walker");
  expectBarIn(img, *inlier, kStaticBarColour, 8.0, "map_inlier static");
  expectBarIn(img, *inlier, kWalkerBarColour, 2.0, "map_inlier walker");
}

TEST(CueEvidence, WriteBenchPlotsDrawsItOnlyForReportsWithHistograms) {
  TempDir tmp;
  BenchResults res;
  res.options.modes = {"off"};
  for (const char* seq : {"with", "without"}) {
    res.sequences.push_back({seq, tmp / seq, ""});  // no groundtruth: no trajectory plots
    RunRecord r;
    r.sequence = seq;
    r.mode = "off";
    r.run = 1;
    r.ok = true;
    r.dir = tmp / (std::string(seq) + "/off/run1");
    r.times.frame_ms = r.times.track_ms = {3, 4, 5};
    r.times.timestamps = {0, 0.03, 0.06};
    std::filesystem::create_directories(r.dir);
    writeFile(r.dir + "/report.json", seq == std::string("with")
                                          ? reportWithHistograms()
                                          : R"({"fps": 30, "mask_scores": {"recall": 0.9}})");
    res.runs.push_back(r);
  }
  BenchReport report(res);
  std::vector<std::string> messages;
  writeBenchPlots(report, tmp.path(), [&](const std::string& m) { messages.push_back(m); });
  EXPECT_EQ(messages, std::vector<std::string>{});
  EXPECT_EQ(cv::imread(tmp / "with/off/cue_evidence.png").size(), cv::Size(1200, 800));
  EXPECT_TRUE(std::filesystem::exists(tmp / "without/off/frame_times.png"));
  EXPECT_FALSE(std::filesystem::exists(tmp / "without/off/cue_evidence.png"));
  const std::string md = report.markdown();
  EXPECT_NE(md.find("with/off/cue_evidence.png"), std::string::npos) << md;
  EXPECT_EQ(md.find("without/off/cue_evidence.png"), std::string::npos) << md;
}

}  // namespace
}  // namespace dynslam
