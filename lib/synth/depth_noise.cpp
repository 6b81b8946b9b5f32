#include "synth/depth_noise.h"

#include <opencv2/imgproc.hpp>

#include <cmath>

namespace dynslam::synth {

double DepthNoise::sigma(double z) { return 0.0012 + 0.0019 * (z - 0.4) * (z - 0.4); }

cv::Mat DepthNoise::apply(const cv::Mat& depth_m, int frame) const {
  CV_Assert(depth_m.type() == CV_32F);
  cv::RNG rng(static_cast<uint64_t>(seed_) * 1000003ull + static_cast<uint64_t>(frame) + 1);
  cv::Mat white(depth_m.size(), CV_32F), drop(depth_m.size(), CV_32F),
      smooth(depth_m.rows / 40 + 2, depth_m.cols / 40 + 2, CV_32F);
  rng.fill(white, cv::RNG::NORMAL, 0, 1);
  rng.fill(drop, cv::RNG::UNIFORM, 0, 1);
  rng.fill(smooth, cv::RNG::NORMAL, 0, 1);
  cv::resize(smooth, smooth, depth_m.size(), 0, 0, cv::INTER_CUBIC);
  // Depth edges: the 3x3 spread exceeds 5 % of the depth.
  cv::Mat dmax, dmin;
  cv::dilate(depth_m, dmax, cv::Mat());
  cv::erode(depth_m, dmin, cv::Mat());
  cv::Mat out(depth_m.size(), CV_16U, cv::Scalar(0));
  const double k = std::sqrt(0.5) * p_.noise_scale;
  for (int r = 0; r < depth_m.rows; ++r) {
    const float* d = depth_m.ptr<float>(r);
    const float* w = white.ptr<float>(r);
    const float* s = smooth.ptr<float>(r);
    const float* hi = dmax.ptr<float>(r);
    const float* lo = dmin.ptr<float>(r);
    const float* u = drop.ptr<float>(r);
    uint16_t* o = out.ptr<uint16_t>(r);
    for (int c = 0; c < depth_m.cols; ++c) {
      const double z = d[c];
      if (!(z >= p_.min_depth && z <= p_.max_depth)) continue;
      if (hi[c] - lo[c] > 0.05 * z && u[c] < p_.edge_dropout) continue;
      const double zn = z + k * sigma(z) * (w[c] + s[c]);
      o[c] = cv::saturate_cast<uint16_t>(std::lround(zn * p_.depth_scale));
    }
  }
  return out;
}

}  // namespace dynslam::synth
