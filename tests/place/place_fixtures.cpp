#include "place_fixtures.h"

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include <random>

#include "features/orb_extractor.h"
#include "place/training_images.h"
#include "testing/test_support.h"

namespace dynslam::test {

cv::Mat rpyDescriptors(int index) {
  static const std::vector<std::string> frames = listTrainingImages({rpyDir()}, 1);
  const cv::Mat gray = cv::imread(frames.at(static_cast<std::size_t>(index)), cv::IMREAD_GRAYSCALE);
  EXPECT_FALSE(gray.empty()) << frames.at(static_cast<std::size_t>(index));
  OrbExtractor extractor;
  std::vector<cv::KeyPoint> kps;
  cv::Mat desc;
  extractor.extract(gray, kps, desc);
  return desc;
}

std::string shippedVocabularyPath() { return sourceDir() + "/configs/orb_vocab_k10_L5.bin"; }

const OrbVocabulary& shippedVocabulary() {
  static const OrbVocabulary voc = OrbVocabulary::load(shippedVocabularyPath());
  return voc;
}

SyntheticClusters makeClusters(int clusters, int per_cluster, int flips, int n_images,
                               unsigned seed) {
  std::mt19937_64 rng(seed);
  SyntheticClusters s;
  for (int c = 0; c < clusters; ++c) s.centres.push_back({rng(), rng(), rng(), rng()});
  std::vector<std::vector<BinaryDescriptor>> rows(static_cast<std::size_t>(n_images));
  s.truth.resize(static_cast<std::size_t>(n_images));
  for (int c = 0; c < clusters; ++c)
    for (int j = 0; j < per_cluster; ++j) {
      BinaryDescriptor d = s.centres[static_cast<std::size_t>(c)];
      for (int f = 0; f < flips; ++f) {
        const unsigned bit = static_cast<unsigned>(rng() % 256);
        d[bit / 64] ^= uint64_t{1} << (bit % 64);
      }
      rows[static_cast<std::size_t>(j % n_images)].push_back(d);
      s.truth[static_cast<std::size_t>(j % n_images)].push_back(c);
    }
  for (const auto& r : rows) {
    cv::Mat m(static_cast<int>(r.size()), 32, CV_8UC1);
    for (std::size_t i = 0; i < r.size(); ++i)
      std::memcpy(m.ptr<uint8_t>(static_cast<int>(i)), r[i].data(), 32);
    s.images.push_back(m);
  }
  return s;
}

}  // namespace dynslam::test
