#pragma once
// Kinect-like corruption of a perfect depth image: axial noise growing with
// the square of the depth (sigma = 1.2 mm + 1.9 mm x (z - 0.4 m)^2, Nguyen et
// al. 2012), half of it per pixel and half as a smooth field (the sensor's
// correlated blotches), no reading outside [min_depth, max_depth] or on
// some pixels of depth edges, and 16-bit quantisation at depth_scale units
// per metre (TUM: 5000). Deterministic from (seed, frame).
#include <opencv2/core.hpp>

namespace dynslam::synth {

struct DepthNoiseParams {
  double noise_scale = 1.0;  ///< x the Kinect sigma (0: exact depth, still quantised)
  double min_depth = 0.4, max_depth = 5.0;  ///< m
  double edge_dropout = 0.5;  ///< probability that a pixel on a depth edge has no reading
  double depth_scale = 5000;
};

class DepthNoise {
 public:
  DepthNoise(const DepthNoiseParams& p, unsigned seed) : p_(p), seed_(seed) {}
  /// depth_m: CV_32F metres (0 = nothing). Returns CV_16U raw units.
  cv::Mat apply(const cv::Mat& depth_m, int frame) const;
  /// The model's axial standard deviation at depth z (m), before noise_scale.
  static double sigma(double z);

 private:
  DepthNoiseParams p_;
  unsigned seed_;
};

}  // namespace dynslam::synth
