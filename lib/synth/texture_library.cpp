#include "synth/texture_library.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace dynslam::synth {

namespace fs = std::filesystem;

namespace {

std::vector<std::string> jpegsIn(const fs::path& dir) {
  std::vector<std::string> out;
  if (!fs::is_directory(dir)) return out;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".jpg") out.push_back(e.path().string());
  std::sort(out.begin(), out.end());
  return out;
}

/// rgb/ files of a TUM folder, every `stride`-th line of rgb.txt.
std::vector<std::string> tumFrames(const fs::path& dir, int stride) {
  std::vector<std::string> out;
  std::ifstream in(dir / "rgb.txt");
  std::string line;
  int n = 0;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ss(line);
    double t;
    std::string file;
    if ((ss >> t >> file) && n++ % stride == 0) out.push_back((dir / file).string());
  }
  return out;
}

}  // namespace

double sharpness(const cv::Mat& bgr) {
  cv::Mat grey, lap;
  cv::cvtColor(bgr, grey, cv::COLOR_BGR2GRAY);
  cv::Laplacian(grey, lap, CV_64F);
  cv::Scalar mean, sd;
  cv::meanStdDev(lap, mean, sd);
  return sd[0] * sd[0];
}

TextureLibrary::TextureLibrary(const std::string& shared_dir, unsigned seed, int rpy_frames,
                               int max_side) {
  const fs::path data = fs::path(shared_dir) / "data";
  for (const char* sub : {"people", "people_more", "objects"})
    for (const std::string& f : jpegsIn(data / sub)) {
      cv::Mat im = cv::imread(f, cv::IMREAD_COLOR);
      if (!im.empty()) photos_.push_back(im);
    }
  std::vector<std::pair<double, cv::Mat>> rpy;
  for (const std::string& f : tumFrames(data / "tum" / "rgbd_dataset_freiburg1_rpy", 36)) {
    cv::Mat im = cv::imread(f, cv::IMREAD_COLOR);
    if (!im.empty()) rpy.emplace_back(sharpness(im), im);
  }
  std::stable_sort(rpy.begin(), rpy.end(),
                   [](const auto& a, const auto& b) { return a.first > b.first; });
  for (int i = 0; i < rpy_frames && i < static_cast<int>(rpy.size()); ++i)
    photos_.push_back(rpy[i].second);
  if (photos_.empty()) throw std::runtime_error("synth: no texture photos under " + data.string());
  for (cv::Mat& im : photos_) {
    const double s = std::min(1.0, double(max_side) / std::max(im.cols, im.rows));
    if (s < 1.0) cv::resize(im, im, cv::Size(), s, s, cv::INTER_AREA);
  }
  // Each photo as is and mirrored left-right (ORB is not mirror invariant).
  for (int i = 0; i < static_cast<int>(photos_.size()); ++i) {
    order_.emplace_back(i, 2);
    order_.emplace_back(i, 1);
  }
  std::mt19937 rng(seed);
  std::shuffle(order_.begin(), order_.end(), rng);
}

cv::Mat TextureLibrary::next() {
  if (used_ >= order_.size()) throw std::runtime_error("synth: ran out of distinct textures");
  const auto [photo, flip] = order_[used_++];
  cv::Mat im = photos_[photo].clone();
  if (flip != 2) cv::flip(im, im, flip);
  return im;
}

}  // namespace dynslam::synth
