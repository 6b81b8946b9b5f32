// OrbExtractor on real fr1_rpy frames, with known geometry (rotation about the
// centre, a 1.2 downscale) and hand-made descriptor cases.
#include <gtest/gtest.h>

#include <opencv2/features2d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "features/orb_extractor.h"
#include "testing/test_support.h"

using namespace dynslam;

namespace {

/// Frame `index` of fr1_rpy (order of rgb.txt), grayscale.
cv::Mat rpyFrame(int index) {
  const std::string dir = test::rpyDir();
  std::ifstream list(dir + "/rgb.txt");
  EXPECT_TRUE(list.good()) << "missing " << dir << "/rgb.txt";
  std::string line;
  int i = 0;
  while (std::getline(list, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (i++ < index) continue;
    std::istringstream ss(line);
    std::string stamp, file;
    ss >> stamp >> file;
    cv::Mat img = cv::imread(dir + "/" + file, cv::IMREAD_GRAYSCALE);
    EXPECT_FALSE(img.empty()) << "cannot read " << file;
    return img;
  }
  ADD_FAILURE() << "fr1_rpy has no frame " << index;
  return {};
}

const std::vector<int> kFrames = {0, 150, 300, 450, 600};

struct Extraction {
  std::vector<cv::KeyPoint> kps;
  cv::Mat desc;
};

Extraction extract(const cv::Mat& img, OrbExtractor& ex) {
  Extraction e;
  ex.extract(img, e.kps, e.desc);
  return e;
}

/// Keypoints per cell of a g x g grid over the image.
std::vector<int> cellCounts(const std::vector<cv::KeyPoint>& kps, cv::Size size, int g) {
  std::vector<int> n(g * g, 0);
  for (const auto& k : kps) {
    const int cx = std::min(g - 1, int(k.pt.x * g / size.width));
    const int cy = std::min(g - 1, int(k.pt.y * g / size.height));
    ++n[cy * g + cx];
  }
  return n;
}

/// Cells of a g x g grid with texture: plain FAST (threshold 10) finds at
/// least `min_corners` corners there.
std::vector<bool> texturedCells(const cv::Mat& img, int g, int min_corners) {
  std::vector<cv::KeyPoint> corners;
  cv::FAST(img, corners, 10, true);
  const std::vector<int> n = cellCounts(corners, img.size(), g);
  std::vector<bool> t(n.size());
  for (size_t i = 0; i < n.size(); ++i) t[i] = n[i] >= min_corners;
  return t;
}

float angleDiff(float a, float b) {
  float d = std::fmod(std::fabs(a - b), 360.f);
  return d > 180.f ? 360.f - d : d;
}

/// Index of the keypoint of `octave` nearest to p within `radius`, or -1.
int nearestAtOctave(const std::vector<cv::KeyPoint>& kps, cv::Point2f p, int octave, float radius) {
  int best = -1;
  float best_d2 = radius * radius;
  for (size_t i = 0; i < kps.size(); ++i) {
    if (kps[i].octave != octave) continue;
    const cv::Point2f d = kps[i].pt - p;
    const float d2 = d.dot(d);
    if (d2 <= best_d2) {
      best_d2 = d2;
      best = static_cast<int>(i);
    }
  }
  return best;
}

}  // namespace

TEST(OrbExtractor, ScalesAndSigmasPerLevel) {
  OrbExtractor ex;
  ASSERT_EQ(ex.levels(), 8);
  ASSERT_EQ(ex.scaleFactors().size(), 8u);
  for (int l = 0; l < 8; ++l) {
    const float s = std::pow(1.2f, float(l));
    EXPECT_NEAR(ex.scaleFactors()[l], s, 1e-5f * s);
    EXPECT_NEAR(ex.invScaleFactors()[l], 1.f / s, 1e-6f);
    EXPECT_NEAR(ex.levelSigma2()[l], s * s, 1e-4f * s * s);
    EXPECT_NEAR(ex.invLevelSigma2()[l], 1.f / (s * s), 1e-6f);
  }
}

TEST(OrbExtractor, RejectsBadParamsAndInput) {
  EXPECT_THROW(OrbExtractor(OrbParams{1000, 1.0f, 8, 20, 7}), std::invalid_argument);
  EXPECT_THROW(OrbExtractor(OrbParams{1000, 1.2f, 0, 20, 7}), std::invalid_argument);
  OrbExtractor ex;
  std::vector<cv::KeyPoint> kps(3);
  cv::Mat desc;
  ex.extract(cv::Mat(), kps, desc);
  EXPECT_TRUE(kps.empty());
  EXPECT_EQ(desc.rows, 0);
  EXPECT_THROW(ex.extract(cv::Mat(480, 640, CV_8UC3, cv::Scalar::all(0)), kps, desc),
               std::invalid_argument);
}

TEST(OrbExtractor, CountLevelsAndKeypointFieldsOnRealFrames) {
  OrbExtractor ex;
  for (int f : kFrames) {
    SCOPED_TRACE("frame " + std::to_string(f));
    const cv::Mat img = rpyFrame(f);
    const Extraction e = extract(img, ex);
    const int n = static_cast<int>(e.kps.size());
    EXPECT_GE(n, 900);
    EXPECT_LE(n, 1100);
    ASSERT_EQ(e.desc.rows, n);
    EXPECT_EQ(e.desc.cols, 32);
    EXPECT_EQ(e.desc.type(), CV_8UC1);

    std::vector<int> per_level(8, 0);
    for (const auto& k : e.kps) {
      ASSERT_GE(k.octave, 0);
      ASSERT_LT(k.octave, 8);
      ++per_level[k.octave];
      EXPECT_GE(k.pt.x, 0.f);
      EXPECT_GE(k.pt.y, 0.f);
      EXPECT_LT(k.pt.x, float(img.cols));
      EXPECT_LT(k.pt.y, float(img.rows));
      EXPECT_NEAR(k.size, 31.f * ex.scaleFactors()[k.octave], 1e-3f);
      EXPECT_GE(k.angle, 0.f);
      EXPECT_LT(k.angle, 360.f);
      EXPECT_GE(k.response, 7.f);  // never below the fallback FAST threshold
    }
    for (int l = 0; l < 8; ++l) EXPECT_GT(per_level[l], 0) << "level " << l << " unused";
    // Finer levels get more features (budget geometric in the level's area).
    EXPECT_GT(per_level[0], per_level[7]);
  }
}

// The reason this class exists: every textured part of the frame gets
// features, where cv::ORB piles them on the strongest corners.
TEST(OrbExtractor, SpreadsFeaturesOverAllTexturedCells) {
  constexpr int kGrid = 4;
  OrbExtractor ex;
  cv::Ptr<cv::ORB> orb = cv::ORB::create(1000, 1.2f, 8);
  int ours_covered = 0, orb_covered = 0, textured_total = 0;
  for (int f : kFrames) {
    SCOPED_TRACE("frame " + std::to_string(f));
    const cv::Mat img = rpyFrame(f);
    const std::vector<bool> textured = texturedCells(img, kGrid, 20);
    const Extraction e = extract(img, ex);
    std::vector<cv::KeyPoint> orb_kps;
    orb->detect(img, orb_kps);
    const std::vector<int> ours = cellCounts(e.kps, img.size(), kGrid);
    const std::vector<int> theirs = cellCounts(orb_kps, img.size(), kGrid);
    // A cell counts as covered when it holds at least a quarter of the
    // uniform share (1000 / 16 / 4 ~ 15 keypoints).
    const int enough = static_cast<int>(e.kps.size()) / (kGrid * kGrid * 4);
    for (int c = 0; c < kGrid * kGrid; ++c) {
      if (!textured[c]) continue;
      ++textured_total;
      EXPECT_GE(ours[c], 5) << "textured cell " << c << " starved";
      ours_covered += ours[c] >= enough;
      orb_covered += theirs[c] >= enough;
    }
  }
  ASSERT_GT(textured_total, 40);  // the frames are mostly textured
  EXPECT_GE(ours_covered, textured_total * 9 / 10);
  EXPECT_GT(ours_covered, orb_covered);
}

// Rotate a real frame about its centre: matched keypoints must keep their
// descriptor and turn their angle with the image.
TEST(OrbExtractor, RotationInvariantWithKnownRotation) {
  const cv::Mat img = rpyFrame(0);
  const double kDeg = 30.0;
  const cv::Point2f centre(img.cols * 0.5f, img.rows * 0.5f);
  const cv::Mat M = cv::getRotationMatrix2D(centre, kDeg, 1.0);
  cv::Mat rotated;
  cv::warpAffine(img, rotated, M, img.size(), cv::INTER_LINEAR, cv::BORDER_CONSTANT);

  OrbExtractor ex;
  const Extraction a = extract(img, ex);
  const Extraction b = extract(rotated, ex);
  auto mapPoint = [&](cv::Point2f p) {
    return cv::Point2f(
        float(M.at<double>(0, 0) * p.x + M.at<double>(0, 1) * p.y + M.at<double>(0, 2)),
        float(M.at<double>(1, 0) * p.x + M.at<double>(1, 1) * p.y + M.at<double>(1, 2)));
  };
  // Expected angle: the keypoint direction pushed through M's linear part.
  auto mapAngle = [&](float deg, double sign) {
    const double r = deg * CV_PI / 180.0;
    const double dx = std::cos(r), dy = std::sin(r);
    const double ex_ = M.at<double>(0, 0) * dx + sign * M.at<double>(0, 1) * dy;
    const double ey = sign * M.at<double>(1, 0) * dx + M.at<double>(1, 1) * dy;
    return float(std::atan2(ey, ex_) * 180.0 / CV_PI);
  };

  int pairs = 0, good = 0, good_wrong_direction = 0;
  for (size_t i = 0; i < a.kps.size(); ++i) {
    const cv::KeyPoint& k = a.kps[i];
    const float scale = ex.scaleFactors()[k.octave];
    const int j = nearestAtOctave(b.kps, mapPoint(k.pt), k.octave, 2.f * scale);
    if (j < 0) continue;
    ++pairs;
    const int dist = descriptorDistance(a.desc.row(int(i)), b.desc.row(j));
    if (dist < 50 && angleDiff(b.kps[j].angle, mapAngle(k.angle, 1.0)) < 10.f) ++good;
    // Control: the opposite rotation must not fit.
    if (angleDiff(b.kps[j].angle, mapAngle(k.angle, -1.0)) < 10.f) ++good_wrong_direction;
  }
  ASSERT_GT(pairs, 200) << "too few repeated keypoints to judge";
  EXPECT_GT(good, pairs / 2) << good << " of " << pairs;
  EXPECT_LT(good_wrong_direction, pairs / 10);
}

// Downscaling by the pyramid factor shifts the pyramid by one level: what was
// found at octave o+1 in the original is found at octave o in the small image.
TEST(OrbExtractor, DownscaleBy1_2ShiftsFeaturesOneOctave) {
  const cv::Mat img = rpyFrame(0);
  cv::Mat small;
  cv::resize(img, small, cv::Size(cvRound(img.cols / 1.2), cvRound(img.rows / 1.2)), 0, 0,
             cv::INTER_LINEAR);
  OrbExtractor ex;
  const Extraction a = extract(img, ex);
  const Extraction b = extract(small, ex);

  int tried = 0, shifted = 0, same_octave = 0;
  for (size_t i = 0; i < a.kps.size(); ++i) {
    const cv::KeyPoint& k = a.kps[i];
    if (k.octave < 1) continue;
    ++tried;
    const cv::Point2f p = k.pt * (1.f / 1.2f);
    const float radius = 2.f * ex.scaleFactors()[k.octave - 1];
    const int j = nearestAtOctave(b.kps, p, k.octave - 1, radius);
    if (j >= 0 && descriptorDistance(a.desc.row(int(i)), b.desc.row(j)) < 50) ++shifted;
    const int s = nearestAtOctave(b.kps, p, k.octave, 2.f * ex.scaleFactors()[k.octave]);
    if (s >= 0 && descriptorDistance(a.desc.row(int(i)), b.desc.row(s)) < 50) ++same_octave;
  }
  ASSERT_GT(tried, 300);
  EXPECT_GT(shifted, tried / 2) << shifted << " of " << tried;
  EXPECT_LT(same_octave, shifted / 2);
}

TEST(DescriptorDistance, CountsDifferingBits) {
  uint8_t a[32] = {}, b[32] = {};
  EXPECT_EQ(descriptorDistance(a, b), 0);
  b[0] = 0xFF;   // 8 bits
  b[10] = 0x80;  // 1
  b[17] = 0x0F;  // 4
  b[31] = 0x01;  // 1 (last byte: checks the last 64-bit word)
  EXPECT_EQ(descriptorDistance(a, b), 14);
  EXPECT_EQ(descriptorDistance(b, a), 14);
  std::memset(a, 0xFF, sizeof a);
  EXPECT_EQ(descriptorDistance(a, b), 256 - 14);

  // Mat overload on rows of a descriptor matrix (unaligned rows too).
  cv::Mat m(3, 33, CV_8UC1, cv::Scalar::all(0));
  cv::Mat rows = m.colRange(1, 33);  // 32-byte rows starting at an odd address
  rows.at<uint8_t>(1, 5) = 0x33;     // 4 bits
  rows.at<uint8_t>(2, 5) = 0x30;     // 2 bits, 2 shared with row 1
  rows.at<uint8_t>(2, 31) = 0xF0;    // 4 bits
  EXPECT_EQ(descriptorDistance(rows.row(0).clone(), rows.row(1).clone()), 4);
  EXPECT_EQ(descriptorDistance(rows.row(1).clone(), rows.row(2).clone()), 6);
  EXPECT_EQ(descriptorDistance(rows.ptr<uint8_t>(1), rows.ptr<uint8_t>(2)), 6);
}

TEST(OrbExtractor, DeterministicAcrossRunsAndInstances) {
  const cv::Mat img = rpyFrame(0), other = rpyFrame(300);
  OrbExtractor ex1, ex2;
  const Extraction first = extract(img, ex1);
  extract(other, ex1);  // reused buffers must not leak into the next frame
  const Extraction again = extract(img, ex1);
  const Extraction fresh = extract(img, ex2);
  for (const Extraction* e : {&again, &fresh}) {
    ASSERT_EQ(e->kps.size(), first.kps.size());
    for (size_t i = 0; i < first.kps.size(); ++i) {
      EXPECT_EQ(e->kps[i].pt, first.kps[i].pt);
      EXPECT_EQ(e->kps[i].angle, first.kps[i].angle);
      EXPECT_EQ(e->kps[i].octave, first.kps[i].octave);
      EXPECT_EQ(e->kps[i].response, first.kps[i].response);
    }
    ASSERT_EQ(e->desc.size(), first.desc.size());
    EXPECT_EQ(cv::norm(e->desc, first.desc, cv::NORM_HAMMING), 0.0);
  }
  // Descriptors of an earlier call are not overwritten by later calls.
  EXPECT_EQ(cv::norm(first.desc, fresh.desc, cv::NORM_HAMMING), 0.0);
}

// Buffers are reused between frames, but never under someone holding them.
TEST(OrbExtractor, KeptPyramidImagesAndCopiesAreNotOverwritten) {
  const cv::Mat img = rpyFrame(0), other = rpyFrame(300);
  OrbExtractor ex;
  extract(img, ex);
  const std::vector<cv::Mat> kept = ex.pyramid();  // shallow: shares buffers
  ASSERT_EQ(kept.size(), 8u);
  const std::vector<cv::Mat> expected = [&] {
    std::vector<cv::Mat> v;
    for (const cv::Mat& m : kept) v.push_back(m.clone());
    return v;
  }();
  OrbExtractor copy = ex;  // cv::Mat members are shallow copies
  const Extraction from_copy = extract(other, copy);
  extract(other, ex);
  for (size_t l = 0; l < kept.size(); ++l)
    EXPECT_EQ(cv::norm(kept[l], expected[l], cv::NORM_INF), 0.0) << "level " << l;
  EXPECT_EQ(cv::norm(ex.pyramid()[0], other, cv::NORM_INF), 0.0);

  OrbExtractor fresh;
  const Extraction ref = extract(other, fresh);
  ASSERT_EQ(from_copy.kps.size(), ref.kps.size());
  EXPECT_EQ(cv::norm(from_copy.desc, ref.desc, cv::NORM_HAMMING), 0.0);
}

// A mover covering half of a real frame (the mask the dynamic stage expects
// it on): the static half keeps the keypoint count a whole frame gets, and
// the mover keeps the same density of its own.
TEST(OrbExtractor, MaskedHalfLeavesTheWholeBudgetToTheStaticHalf) {
  const cv::Mat img = rpyFrame(150);
  ASSERT_FALSE(img.empty());
  OrbExtractor ex;
  const Extraction plain = extract(img, ex);
  cv::Mat mask(img.size(), CV_8U, cv::Scalar(0));
  mask(cv::Rect(0, 0, img.cols / 2, img.rows)).setTo(255);
  Extraction masked;
  ex.extract(img, masked.kps, masked.desc, mask);
  ASSERT_EQ(masked.desc.rows, int(masked.kps.size()));
  int plain_static = 0, static_kps = 0, on_mask = 0;
  for (const auto& k : plain.kps) plain_static += k.pt.x >= img.cols / 2;
  for (const auto& k : masked.kps) (k.pt.x >= img.cols / 2 ? static_kps : on_mask)++;
  // Without the mask the static half gets about half of the budget...
  EXPECT_LT(plain_static, 0.7 * double(plain.kps.size()));
  // ...with it, at least 90 % of the whole frame's count.
  EXPECT_GE(static_kps, 0.9 * double(plain.kps.size()));
  EXPECT_GT(on_mask, 0.3 * double(plain.kps.size()));
  // Grouped by level as always.
  for (std::size_t i = 1; i < masked.kps.size(); ++i)
    ASSERT_LE(masked.kps[i - 1].octave, masked.kps[i].octave);
  // An empty mask changes nothing.
  Extraction none;
  ex.extract(img, none.kps, none.desc, cv::Mat(img.size(), CV_8U, cv::Scalar(0)));
  EXPECT_EQ(none.kps.size(), plain.kps.size());
}

TEST(OrbExtractor, BadMaskIsRejected) {
  OrbExtractor ex;
  const cv::Mat img(240, 320, CV_8U, cv::Scalar(0));
  std::vector<cv::KeyPoint> kps;
  cv::Mat desc;
  EXPECT_THROW(ex.extract(img, kps, desc, cv::Mat(100, 100, CV_8U, cv::Scalar(0))),
               std::invalid_argument);
  EXPECT_THROW(ex.extract(img, kps, desc, cv::Mat(240, 320, CV_16U, cv::Scalar(0))),
               std::invalid_argument);
}
