#include "place/training_images.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <stdexcept>

#include "core/errors.h"
#include "rawlog/image_decoder.h"
#include "rawlog/sequence_source.h"

namespace dynslam {

namespace fs = std::filesystem;

namespace {

bool hasImageExtension(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  for (const char* e : {".png", ".jpg", ".jpeg", ".bmp", ".ppm", ".pgm", ".tif", ".tiff"})
    if (ext == e) return true;
  return false;
}

std::vector<std::string> folderImages(const std::string& dir) {
  if (fs::is_regular_file(fs::path(dir) / "rgb.txt")) {
    std::vector<std::string> v;
    for (const TumListEntry& e : readTumList(dir + "/rgb.txt")) v.push_back(dir + "/" + e.file);
    return v;
  }
  std::vector<std::string> v;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec))
    if (entry.is_regular_file() && hasImageExtension(entry.path()))
      v.push_back(entry.path().string());
  if (ec) throw InputError(dir, "cannot list folder (" + ec.message() + ")");
  std::sort(v.begin(), v.end());
  return v;
}

}  // namespace

std::vector<std::string> listTrainingImages(const std::vector<std::string>& inputs, int stride) {
  if (stride < 1)
    throw std::invalid_argument("stride must be at least 1, got " + std::to_string(stride));
  std::vector<std::string> images;
  for (const std::string& in : inputs) {
    std::error_code ec;
    if (fs::is_regular_file(in, ec)) {
      images.push_back(in);
      continue;
    }
    if (!fs::is_directory(in, ec)) throw InputError(in, "no such image file or folder");
    const std::vector<std::string> all = folderImages(in);
    if (all.empty()) throw InputError(in, "folder holds no images (and no TUM rgb.txt)");
    for (std::size_t i = 0; i < all.size(); i += static_cast<std::size_t>(stride))
      images.push_back(all[i]);
  }
  return images;
}

std::vector<cv::Mat> extractTrainingDescriptors(
    const std::vector<std::string>& images, const OrbParams& orb,
    const std::function<void(std::size_t, std::size_t)>& progress) {
  OrbExtractor extractor(orb);
  std::vector<cv::Mat> out;
  out.reserve(images.size());
  std::vector<cv::KeyPoint> keypoints;
  for (const std::string& path : images) {
    const cv::Mat gray = decodeImageFile(path, DecodedImage::kGray8, "training image");
    cv::Mat descriptors;
    extractor.extract(gray, keypoints, descriptors);
    out.push_back(descriptors);
    if (progress) progress(out.size(), images.size());
  }
  return out;
}

}  // namespace dynslam
