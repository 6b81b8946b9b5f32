// Benchmark of the dynamic-object building blocks (lib/dynamic):
//   1. detector forward time per model (median of --runs passes, reused blob),
//   2. motion check time per frame on consecutive real fr1_rpy frames,
//   3. with --composite DIR: recall / false rejection of the motion check and
//      of the box-depth mask on a sequence from make_dynamic_sequence.py.
//
// usage: bench_dynamic [--runs N] [--pairs N] [--points N] [--threads N]
//                      [--composite DIR] [--frames N] [--no-detector]
//                      [--lk-window PX] [--lk-levels N] [--lk-iters N]
//                      [--epi-px PX] [--reproj-px PX]   (motion check parameters)
#include <opencv2/features2d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <time.h>

#include "core/camera.h"
#include "core/data_paths.h"
#include "core/stats.h"
#include "core/timing.h"
#include "core/trajectory.h"
#include "dynamic/depth_masks.h"
#include "dynamic/motion_check.h"
#include "dynamic/yolo_detector.h"
#include "eval/mask_scoring.h"
#include "rawlog/tum_folder_source.h"

using namespace dynslam;

namespace {

struct Seq {
  std::vector<std::string> rgb, depth;  // associated pairs, full paths
  std::vector<cv::Matx44d> pose_wc;     // groundtruth camera-to-world per pair
};

// The sequence's associated RGB-D pairs, read by the project's TUM reader
// (fr1 camera given explicitly: composite folders may have any name).
Seq loadSeq(const std::string& dir) {
  Seq s;
  try {
    const dynslam::TumFolderSource src(dir, DYNSLAM_SOURCE_DIR "/configs/tum_fr1.yaml");
    // The motion check runs under the camera motion the tracker's poses
    // give; here the groundtruth's stands in for them.
    const dynslam::Trajectory gt = dynslam::readTumTrajectory(dir + "/groundtruth.txt");
    for (std::size_t i = 0; i < src.size(); ++i) {
      const dynslam::StampedPose* p = dynslam::nearestPose(gt, src.timestamp(i), 0.02);
      if (!p) continue;  // no groundtruth for the pair
      s.rgb.push_back(src.rgbPath(i));
      s.depth.push_back(src.depthPath(i));
      s.pose_wc.push_back(dynslam::toMatx(p->pose));
    }
  } catch (const std::exception& e) {
    std::cerr << e.what() << "\n";
    std::exit(1);
  }
  return s;
}

// FAST corners bucketed on a grid (the tracker's ORB extractor also spreads
// its corners; this is a stand-in that needs no other module).
std::vector<cv::Point2f> gridFast(const cv::Mat& gray, int n) {
  const int gx = 8, gy = 6, per = std::max(1, n / (gx * gy));
  std::vector<cv::Point2f> pts;
  for (int cy = 0; cy < gy; ++cy)
    for (int cx = 0; cx < gx; ++cx) {
      const cv::Rect cell(cx * gray.cols / gx, cy * gray.rows / gy, gray.cols / gx, gray.rows / gy);
      std::vector<cv::KeyPoint> kps;
      for (int thr : {20, 7}) {
        cv::FAST(gray(cell), kps, thr, true);
        if (int(kps.size()) >= per) break;
      }
      cv::KeyPointsFilter::retainBest(kps, per);
      for (const auto& k : kps) pts.emplace_back(k.pt.x + cell.x, k.pt.y + cell.y);
    }
  return pts;
}

std::string fmt(double v, int prec = 2) {
  char b[64];
  std::snprintf(b, sizeof b, "%.*f", prec, v);
  return b;
}

}  // namespace

int main(int argc, char** argv) {
  int runs = 20, pairs = 40, points = 1000, threads = 0, frames = 40;
  bool detector = true;
  std::string composite;
  MotionCheckParams mp;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::cerr << a << " needs a value\n";
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--runs")
      runs = std::stoi(next());
    else if (a == "--pairs")
      pairs = std::stoi(next());
    else if (a == "--points")
      points = std::stoi(next());
    else if (a == "--threads")
      threads = std::stoi(next());
    else if (a == "--composite")
      composite = next();
    else if (a == "--frames")
      frames = std::stoi(next());
    else if (a == "--no-detector")
      detector = false;
    else if (a == "--lk-window")
      mp.lk_window = std::stoi(next());
    else if (a == "--lk-levels")
      mp.lk_max_level = std::stoi(next());
    else if (a == "--lk-iters")
      mp.lk_iterations = std::stoi(next());
    else if (a == "--epi-px")
      mp.epipolar_threshold_px = std::stof(next());
    else if (a == "--reproj-px")
      mp.reprojection_threshold_px = std::stof(next());
    else {
      std::cerr << "usage: bench_dynamic [--runs N] [--pairs N] [--points N] [--threads N] "
                   "[--composite DIR] [--frames N] [--no-detector] [--lk-window PX] "
                   "[--lk-levels N] [--lk-iters N] [--epi-px PX] [--reproj-px PX]\n";
      return 2;
    }
  }
  if (threads > 0) cv::setNumThreads(threads);
  std::cout << "OpenCV threads: " << cv::getNumThreads() << "\n";
  const std::string shared = sharedDataDir();
  const std::string rpy = shared + "/data/tum/rgbd_dataset_freiburg1_rpy";
  const PinholeCamera cam = loadCameraYaml(configDir() + "/tum_fr1.yaml");
  const Seq seq = loadSeq(rpy);
  const cv::Mat frame0 = cv::imread(seq.rgb[0]);

  // 1. Detector forward times.
  if (detector) {
    std::cout << "\n## detector (median of " << runs << " forward passes on " << seq.rgb[0]
              << ")\n";
    for (const char* m : {"yolov5n_480x640", "yolov5n_416x416", "yolov5n_320x320", "yolox_nano"}) {
      YoloDetectorParams p;
      p.model_path = shared + "/models/" + m + ".onnx";
      YoloDetector det(p);
      std::vector<double> fwd, total, cpu;
      std::size_t n = 0;
      det.detect(frame0);  // warm-up
      for (int r = 0; r < runs; ++r) {
        const int64 t0 = cv::getTickCount();
        const double c0 = dynslam::processCpuMs();
        n = det.detect(frame0).size();
        cpu.push_back(dynslam::processCpuMs() - c0);
        total.push_back(double(cv::getTickCount() - t0) * 1000 / cv::getTickFrequency());
        fwd.push_back(det.lastForwardMs());
      }
      std::cout << m << " (" << yoloLayoutName(det.layout()) << ", " << det.inputSize().width << "x"
                << det.inputSize().height << "): forward " << fmt(summarize(fwd).median)
                << " ms, detect() total " << fmt(summarize(total).median) << " ms (CPU "
                << fmt(summarize(cpu).median) << " ms), " << n << " detections\n";
    }
  }

  // 2. Motion check time on real consecutive frames.
  {
    MotionConsistencyCheck check(mp);
    BoxDepthMasker boxes_masker;
    std::vector<double> t_frame, t_cpu, t_track, t_geo, t_mask, t_pyr, t_box, n_tracked, n_dyn;
    const int count = std::min<int>(pairs + 1, int(seq.rgb.size()));
    MotionFrame prev;
    std::vector<cv::Point2f> pts;
    for (int i = 0; i < count; ++i) {
      const cv::Mat rgb = cv::imread(seq.rgb[i]);
      const cv::Mat depth = cv::imread(seq.depth[i], cv::IMREAD_UNCHANGED);
      cv::Mat gray;
      cv::cvtColor(rgb, gray, cv::COLOR_BGR2GRAY);
      int64 t0 = cv::getTickCount();
      const double c0 = dynslam::processCpuMs();
      MotionFrame cur = check.makeFrame(gray, depth);
      const double pyr = double(cv::getTickCount() - t0) * 1000 / cv::getTickFrequency();
      if (i > 0) {
        t0 = cv::getTickCount();
        std::vector<uint8_t> ok;
        const std::vector<cv::Point2f> moved = check.track(prev, cur, pts, ok);
        const double ms_track = double(cv::getTickCount() - t0) * 1000 / cv::getTickFrequency();
        const MotionResult r =
            check.classify(pts, moved, ok, prev.depth, cur.depth, cam, {}, {}, nullptr,
                           cameraMotionBetween(seq.pose_wc[i - 1], seq.pose_wc[i]));
        t_cpu.push_back(dynslam::processCpuMs() - c0);
        t_frame.push_back(double(cv::getTickCount() - t0) * 1000 / cv::getTickFrequency() + pyr);
        t_pyr.push_back(pyr);
        t_track.push_back(ms_track);
        t_geo.push_back(r.ms_geometry);
        t_mask.push_back(r.ms_mask);
        n_tracked.push_back(double(r.tracked_index.size()));
        n_dyn.push_back(double(std::count(r.dynamic.begin(), r.dynamic.end(), 1)));
        Detection fake;  // one person-sized box, to time the box mask
        fake.box = cv::Rect2f(200, 100, 180, 360);
        fake.dynamic_class = true;
        t0 = cv::getTickCount();
        boxes_masker.computeFromBoxes(depth, cam.depth_scale, {fake});
        t_box.push_back(double(cv::getTickCount() - t0) * 1000 / cv::getTickFrequency());
      }
      pts = gridFast(prev.gray.empty() ? gray : gray, points);
      prev = std::move(cur);
    }
    std::cout << "\n## motion check on " << t_frame.size() << " consecutive fr1_rpy pairs, "
              << points << " FAST points requested\n"
              << "per frame median " << fmt(summarize(t_frame).median) << " ms (p95 "
              << fmt(summarize(t_frame).p95) << ", CPU " << fmt(summarize(t_cpu).median)
              << " ms): pyramid " << fmt(summarize(t_pyr).median) << ", LK fwd+bwd "
              << fmt(summarize(t_track).median) << ", tests under the groundtruth motion "
              << fmt(summarize(t_geo).median) << ", region growing "
              << fmt(summarize(t_mask).median) << " ms\n"
              << "tracked " << fmt(summarize(n_tracked).median, 0) << " points, flagged dynamic "
              << fmt(summarize(n_dyn).median, 0) << " (median; static scene)\n"
              << "box depth mask (one 180x360 box): " << fmt(summarize(t_box).median, 3) << " ms\n";
  }

  // 3. Composite sequence with ground-truth masks.
  if (!composite.empty()) {
    const Seq cs = loadSeq(composite);
    std::unique_ptr<YoloDetector> det;
    if (detector) det = std::make_unique<YoloDetector>();
    MotionConsistencyCheck check(mp);
    BoxDepthMasker masker;
    MaskScore motion_only, motion_boxes, box_mask, combined;
    double px_walk = 0, px_walk_hit = 0, px_static = 0, px_static_hit = 0;
    MotionFrame prev;
    std::vector<cv::Point2f> pts;
    cv::Mat prev_mask_gt;
    std::vector<Detection> prev_dets;
    const int count = std::min<int>(frames, int(cs.rgb.size()));
    for (int i = 0; i < count; ++i) {
      const cv::Mat rgb = cv::imread(cs.rgb[i]);
      const cv::Mat depth = cv::imread(cs.depth[i], cv::IMREAD_UNCHANGED);
      std::string name = cs.rgb[i].substr(cs.rgb[i].find_last_of('/') + 1);
      const cv::Mat gt = cv::imread(composite + "/masks/" + name, cv::IMREAD_GRAYSCALE);
      if (gt.empty()) {
        std::cerr << composite << "/masks/" << name << ": missing mask\n";
        return 1;
      }
      MotionFrame cur = check.makeFrame(rgb, depth);
      std::vector<Detection> dets;
      if (det) dets = det->detect(rgb);
      if (i > 0) {
        // Points of the previous frame, scored against the previous mask.
        std::vector<uint8_t> ok;
        const std::vector<cv::Point2f> moved = check.track(prev, cur, pts, ok);
        const CameraMotion known = cameraMotionBetween(cs.pose_wc[i - 1], cs.pose_wc[i]);
        const MotionResult a =
            check.classify(pts, moved, ok, prev.depth, cur.depth, cam, {}, {}, nullptr, known);
        const MotionResult b =
            check.classify(pts, moved, ok, prev.depth, cur.depth, cam, dets, {}, nullptr, known);
        std::vector<cv::Point2f> tp;
        std::vector<uint8_t> fa, fb, fbox, fc;
        const cv::Mat bm = masker.computeFromBoxes(prev.depth, cam.depth_scale, prev_dets);
        for (std::size_t k = 0; k < pts.size(); ++k) {
          if (!a.tracked[k]) continue;
          tp.push_back(pts[k]);
          fa.push_back(a.dynamic[k]);
          fb.push_back(b.dynamic[k]);
          const cv::Point q(cvRound(pts[k].x), cvRound(pts[k].y));
          const uint8_t inbox = bm.at<uint8_t>(q) ? 1 : 0;
          fbox.push_back(inbox);
          fc.push_back(b.dynamic[k] || inbox);
        }
        motion_only += scoreKeypoints(tp, fa, prev_mask_gt);
        motion_boxes += scoreKeypoints(tp, fb, prev_mask_gt);
        box_mask += scoreKeypoints(tp, fbox, prev_mask_gt);
        combined += scoreKeypoints(tp, fc, prev_mask_gt);
        // Pixel level: grown motion mask (of the current frame) vs current truth.
        const cv::Mat walk = (gt > 0) & (gt < 128), stat = gt == 0;
        px_walk += cv::countNonZero(walk);
        px_walk_hit += cv::countNonZero(walk & b.mask);
        px_static += cv::countNonZero(stat);
        px_static_hit += cv::countNonZero(stat & b.mask);
      }
      pts = gridFast(cur.gray, points);
      prev = std::move(cur);
      prev_mask_gt = gt;
      prev_dets = dets;
    }
    auto line = [](const char* what, const MaskScore& s) {
      std::cout << what << ": walker recall " << fmt(s.recall(), 3) << " (" << s.walker_flagged
                << "/" << s.walker_points << "), static false rejection "
                << fmt(s.falseRejectionRate(), 4) << " (" << s.static_flagged << "/"
                << s.static_points << "), standing-still rejected "
                << fmt(s.standingRejectionRate(), 3) << " (" << s.standing_flagged << "/"
                << s.standing_points << ")\n";
    };
    std::cout << "\n## composite " << composite << " (" << count - 1 << " frame pairs)\n";
    line("motion check, no boxes      ", motion_only);
    if (det) {
      line("motion check, with boxes    ", motion_boxes);
      line("box depth mask only         ", box_mask);
      line("motion check OR box mask    ", combined);
    }
    std::cout << "grown motion mask (pixels): walker recall " << fmt(px_walk_hit / px_walk, 3)
              << ", static pixels flagged " << fmt(px_static_hit / px_static, 4) << "\n";
  }
  return 0;
}
