#pragma once
// Pieces of the small synthetic RGB-D scenes the dynamic-stage tests render:
// a 320x240 pinhole camera (f = 300 px, no distortion, 5000 units per metre)
// and blurred random textures that LK tracks well.
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include <vector>

#include "core/camera.h"

namespace dynslam::test {

inline constexpr int kSceneWidth = 320, kSceneHeight = 240;

inline PinholeCamera sceneCamera() {
  PinholeCamera cam;
  cam.width = kSceneWidth;
  cam.height = kSceneHeight;
  cam.fx = cam.fy = 300;
  cam.cx = 160;
  cam.cy = 120;
  cam.depth_scale = 5000;
  return cam;
}

/// Uniform noise blurred by sigma 1.5 px and stretched to 0..255.
inline cv::Mat noiseTexture(cv::RNG& rng, cv::Size size) {
  cv::Mat noise(size, CV_8U);
  rng.fill(noise, cv::RNG::UNIFORM, 0, 255);
  cv::GaussianBlur(noise, noise, cv::Size(0, 0), 1.5);
  cv::normalize(noise, noise, 0, 255, cv::NORM_MINMAX);
  return noise;
}

/// The strong corners of a grey image (up to 800, 5 px apart) as keypoints
/// of size 7: what the scenes' frames are judged on.
inline std::vector<cv::KeyPoint> cornerKeypoints(const cv::Mat& gray) {
  std::vector<cv::Point2f> corners;
  cv::goodFeaturesToTrack(gray, corners, 800, 0.01, 5);
  std::vector<cv::KeyPoint> keys;
  for (const auto& c : corners) keys.emplace_back(c, 7.f);
  return keys;
}

}  // namespace dynslam::test
