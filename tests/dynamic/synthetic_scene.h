#pragma once
// Pieces of the small synthetic RGB-D scenes the dynamic-stage tests render:
// a 320x240 pinhole camera (f = 300 px, no distortion, 5000 units per metre)
// and blurred random textures that LK tracks well.
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

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

}  // namespace dynslam::test
