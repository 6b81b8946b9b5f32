// FeatureMatcher on a synthetic scene with known geometry: random 3D points
// seen by two cameras with known poses; keypoints are the exact projections
// and a point has the same random descriptor in both views, so every correct
// match is known in advance. Distractor keypoints with random descriptors
// (Hamming distance ~128 to anything) sit among them.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <map>
#include <memory>
#include <random>
#include <set>

#include "features/orb_extractor.h"
#include "map/map.h"
#include "matching/feature_matcher.h"

using namespace dynslam;
using mrpt::poses::CPose3D;

namespace {

struct View {
  std::shared_ptr<FeatureSet> fs;
  std::vector<int> key_of_point;  ///< scene point -> keypoint index (-1: none)
  std::vector<int> point_of_key;  ///< keypoint index -> scene point (-1: distractor)
};

struct Scene {
  std::shared_ptr<FrameContext> ctx = idealFrameContext();
  std::vector<Eigen::Vector3d> points;
  cv::Mat point_desc;  ///< one random descriptor per scene point
  CameraPose pose1{CPose3D()};
  CameraPose pose2{CPose3D(0.3, 0.05, 0.1, 0.08, -0.03, 0.02)};  // ~5 deg yaw
  std::mt19937 rng{42};

  /// Points in front of both cameras, projecting inside both images with a
  /// 20 px margin.
  explicit Scene(int n) {
    std::uniform_real_distribution<double> ux(-2, 2), uy(-1.5, 1.5), uz(2, 6);
    while (static_cast<int>(points.size()) < n) {
      const Eigen::Vector3d p(ux(rng), uy(rng), uz(rng));
      bool ok = true;
      for (const CameraPose* cp : {&pose1, &pose2}) {
        const Eigen::Vector3d pc = cp->toCamera(p);
        const Eigen::Vector2d uv = ctx->proj.project(pc);
        ok = ok && pc.z() > 0.5 && uv.x() > 20 && uv.x() < 620 && uv.y() > 20 && uv.y() < 460;
      }
      if (ok) points.push_back(p);
    }
    point_desc = cv::Mat(n, 32, CV_8UC1);
    cv::randu(point_desc, 0, 256);
  }

  /// Keypoints of the scene points (shuffled) plus `distractors` random
  /// keypoints. with_depth: depth and ur from the true camera-frame depth.
  View view(const CameraPose& pose, bool with_depth, int distractors) {
    const int n = static_cast<int>(points.size());
    std::vector<int> order(n + distractors);
    for (int i = 0; i < n + distractors; ++i) order[i] = i;
    std::shuffle(order.begin(), order.end(), rng);
    View v;
    v.fs = std::make_shared<FeatureSet>();
    v.fs->ctx = ctx;
    v.key_of_point.assign(n, -1);
    v.point_of_key.assign(order.size(), -1);
    v.fs->descriptors = cv::Mat(static_cast<int>(order.size()), 32, CV_8UC1);
    std::uniform_real_distribution<float> ux(5, 635), uy(5, 475);
    std::vector<float> z(order.size(), -1.f);
    for (std::size_t k = 0; k < order.size(); ++k) {
      const int s = order[k];
      if (s < n) {
        const Eigen::Vector3d pc = pose.toCamera(points[s]);
        const Eigen::Vector2d uv = ctx->proj.project(pc);
        v.fs->keys.emplace_back(static_cast<float>(uv.x()), static_cast<float>(uv.y()), 31.f, 0.f,
                                0.f, 0);
        point_desc.row(s).copyTo(v.fs->descriptors.row(static_cast<int>(k)));
        v.key_of_point[s] = static_cast<int>(k);
        v.point_of_key[k] = s;
        z[k] = static_cast<float>(pc.z());
      } else {
        v.fs->keys.emplace_back(ux(rng), uy(rng), 31.f, 0.f, 0.f, 0);
        cv::Mat row = v.fs->descriptors.row(static_cast<int>(k));
        cv::randu(row, 0, 256);
        z[k] = 3.5f;
      }
    }
    v.fs->finalize(cv::Mat());  // no depth image: depth -1 everywhere
    if (with_depth)
      for (std::size_t k = 0; k < order.size(); ++k) {
        v.fs->depth[k] = z[k];
        v.fs->ur[k] = static_cast<float>(v.fs->keys_un[k].pt.x - v.fs->ctx->proj.bf / z[k]);
      }
    return v;
  }
};

/// A keyframe for the view with one map point per scene point it sees.
KeyFrame* keyFrameWithPoints(Map& map, const Scene& scene, const View& v, const CameraPose& pose,
                             std::vector<MapPoint*>* points_out) {
  KeyFrame* kf = map.createKeyFrame(static_cast<long>(map.keyFrameCount()), 0.0,
                                    map.keyFrameCount(), v.fs, pose);
  std::vector<MapPoint*> pts(scene.points.size(), nullptr);
  for (std::size_t s = 0; s < scene.points.size(); ++s) {
    const int k = v.key_of_point[s];
    if (k < 0) continue;
    MapPoint* mp = map.createMapPoint(scene.points[s], kf);
    mp->addObservation(kf, k);
    kf->addPoint(mp, k);
    mp->updateDescriptor();
    mp->updateNormalAndDepth();
    pts[s] = mp;
  }
  if (points_out) *points_out = pts;
  return kf;
}

/// Counts (correct, wrong) associations of cur.points against the scene.
std::pair<int, int> score(const Frame& cur, const View& v,
                          const std::map<const MapPoint*, int>& scene_of) {
  int good = 0, bad = 0;
  for (std::size_t k = 0; k < cur.points.size(); ++k) {
    if (!cur.points[k]) continue;
    auto it = scene_of.find(cur.points[k]);
    if (it != scene_of.end() && it->second == v.point_of_key[k])
      ++good;
    else
      ++bad;
  }
  return {good, bad};
}

std::map<const MapPoint*, int> sceneIndex(const std::vector<MapPoint*>& pts) {
  std::map<const MapPoint*, int> m;
  for (std::size_t s = 0; s < pts.size(); ++s)
    if (pts[s]) m[pts[s]] = static_cast<int>(s);
  return m;
}

/// Sampson-free epipolar residual in pixels: distance of x2 to the epipolar
/// line of x1, from the known poses (computed here independently of the
/// matcher, through normalised coordinates and the essential matrix).
double epipolarDistance(const Scene& sc, const cv::Point2f& x1, const cv::Point2f& x2) {
  const auto& P = sc.ctx->proj;
  const Eigen::Matrix3d R21 = sc.pose2.Rcw() * sc.pose1.Rwc();
  const Eigen::Vector3d t21 = sc.pose2.toCamera(sc.pose1.center());  // centre 1 in camera 2
  Eigen::Matrix3d tx;
  tx << 0, -t21.z(), t21.y(), t21.z(), 0, -t21.x(), -t21.y(), t21.x(), 0;
  const Eigen::Matrix3d E = tx * R21;  // x2n^T E x1n = 0
  const Eigen::Vector3d n1((x1.x - P.cx) / P.fx, (x1.y - P.cy) / P.fy, 1);
  const Eigen::Vector3d n2((x2.x - P.cx) / P.fx, (x2.y - P.cy) / P.fy, 1);
  const Eigen::Vector3d l = E * n1;  // line in camera 2 (normalised)
  return std::abs(n2.dot(l)) / std::hypot(l.x(), l.y()) * P.fx;
}

}  // namespace

TEST(SyntheticScene, ConstructionIsConsistent) {
  Scene sc(150);
  const View v = sc.view(sc.pose2, true, 30);
  ASSERT_EQ(v.fs->size(), 180u);
  for (std::size_t s = 0; s < sc.points.size(); ++s) {
    const int k = v.key_of_point[s];
    ASSERT_GE(k, 0);
    const Eigen::Vector3d back = sc.pose2.toWorld(v.fs->unprojectCamera(k));
    EXPECT_NEAR((back - sc.points[s]).norm(), 0, 1e-4);
    EXPECT_EQ(descriptorDistance(v.fs->descriptor(k), sc.point_desc.ptr<uint8_t>(int(s))), 0);
  }
}

TEST(FeatureMatcher, SearchByProjectionFrameToFrameWithTruePose) {
  Scene sc(200);
  const View v1 = sc.view(sc.pose1, true, 50);
  const View v2 = sc.view(sc.pose2, true, 50);
  Map map;
  std::vector<MapPoint*> pts;
  KeyFrame* kf = keyFrameWithPoints(map, sc, v1, sc.pose1, &pts);
  Frame last(0, 0, 0.0, v1.fs);
  last.setPose(sc.pose1.wc());
  last.points = kf->points;
  last.ref_kf = kf;
  Frame cur(1, 1, 0.03, v2.fs);
  cur.setPose(sc.pose2.wc());

  FeatureMatcher m;
  const int n = m.searchByProjection(cur, last, 7.f);
  const auto [good, bad] = score(cur, v2, sceneIndex(pts));
  EXPECT_EQ(n, good + bad);
  RecordProperty("correct_matches", good);
  EXPECT_GE(good, 196);  // (nearly) all 200
  EXPECT_EQ(bad, 0);
  EXPECT_EQ(cur.matchedCount(), n);
  // Distractor keypoints never get a point.
  for (std::size_t k = 0; k < cur.points.size(); ++k)
    if (v2.point_of_key[k] < 0) {
      EXPECT_EQ(cur.points[k], nullptr);
    }
}

// The search is guided by the pose: with a pose 0.5 m off and a small window,
// the projections land far from the true keypoints and little is matched.
TEST(FeatureMatcher, SearchByProjectionNeedsTheRightPose) {
  Scene sc(200);
  const View v1 = sc.view(sc.pose1, true, 50);
  const View v2 = sc.view(sc.pose2, true, 50);
  Map map;
  std::vector<MapPoint*> pts;
  KeyFrame* kf = keyFrameWithPoints(map, sc, v1, sc.pose1, &pts);
  Frame last(0, 0, 0.0, v1.fs);
  last.setPose(sc.pose1.wc());
  last.points = kf->points;
  Frame cur(1, 1, 0.03, v2.fs);
  cur.setPose(sc.pose2.wc() + CPose3D(0.5, 0, 0, 0, 0, 0));
  FeatureMatcher m;
  const int n = m.searchByProjection(cur, last, 2.f);
  RecordProperty("matches", n);
  EXPECT_LT(n, 20);
  const auto [good, bad] = score(cur, v2, sceneIndex(pts));
  EXPECT_EQ(bad, 0);  // what is matched is still right (descriptors are unique)
  (void)good;
}

// Points marked outliers in the last frame are not propagated.
TEST(FeatureMatcher, SearchByProjectionSkipsLastFrameOutliers) {
  Scene sc(100);
  const View v1 = sc.view(sc.pose1, true, 0);
  const View v2 = sc.view(sc.pose2, true, 0);
  Map map;
  std::vector<MapPoint*> pts;
  KeyFrame* kf = keyFrameWithPoints(map, sc, v1, sc.pose1, &pts);
  Frame last(0, 0, 0.0, v1.fs);
  last.setPose(sc.pose1.wc());
  last.points = kf->points;
  for (std::size_t k = 0; k < last.outlier.size(); k += 2) last.outlier[k] = 1;
  Frame cur(1, 1, 0.03, v2.fs);
  cur.setPose(sc.pose2.wc());
  FeatureMatcher m;
  const int n = m.searchByProjection(cur, last, 7.f);
  EXPECT_EQ(n, 50);
  for (std::size_t k = 0; k < last.outlier.size(); k += 2) {
    const int s = v1.point_of_key[k];
    EXPECT_EQ(cur.points[v2.key_of_point[s]], nullptr);
  }
}

// Local-map search: the caller (tracker) fills each point's projection into
// the current frame; here from the true pose. Points not flagged in view are
// skipped.
TEST(FeatureMatcher, SearchByProjectionLocalMapPoints) {
  Scene sc(200);
  const View v1 = sc.view(sc.pose1, true, 50);
  const View v2 = sc.view(sc.pose2, true, 50);
  Map map;
  std::vector<MapPoint*> pts;
  keyFrameWithPoints(map, sc, v1, sc.pose1, &pts);
  for (std::size_t s = 0; s < pts.size(); ++s) {
    MapPoint* mp = pts[s];
    const Eigen::Vector3d pc = sc.pose2.toCamera(mp->pos);
    const Eigen::Vector3d uvr = sc.ctx->proj.projectStereo(pc);
    mp->track_in_view = s % 10 != 0;  // every tenth point: not in view
    mp->proj_x = static_cast<float>(uvr.x());
    mp->proj_y = static_cast<float>(uvr.y());
    mp->proj_ur = static_cast<float>(uvr.z());
    mp->pred_level = mp->predictScale((mp->pos - sc.pose2.center()).norm(), *sc.ctx);
    mp->view_cos = 1.f;
  }
  Frame cur(1, 1, 0.03, v2.fs);
  cur.setPose(sc.pose2.wc());
  FeatureMatcher m;
  const int n = m.searchByProjection(cur, pts, 1.f);
  const auto [good, bad] = score(cur, v2, sceneIndex(pts));
  EXPECT_EQ(n, good + bad);
  EXPECT_EQ(bad, 0);
  EXPECT_GE(good, 176);  // 180 in view
  EXPECT_LE(good, 180);
  for (std::size_t s = 0; s < pts.size(); s += 10)
    EXPECT_EQ(cur.points[v2.key_of_point[s]], nullptr);
}

TEST(FeatureMatcher, SearchByDescriptorWithoutPose) {
  Scene sc(200);
  const View v1 = sc.view(sc.pose1, true, 50);
  const View v2 = sc.view(sc.pose2, true, 80);
  Map map;
  std::vector<MapPoint*> pts;
  KeyFrame* kf = keyFrameWithPoints(map, sc, v1, sc.pose1, &pts);
  Frame cur(1, 1, 0.03, v2.fs);  // no pose at all
  FeatureMatcher m;
  const int n = m.searchByDescriptor(*kf, cur);
  const auto [good, bad] = score(cur, v2, sceneIndex(pts));
  RecordProperty("correct_matches", good);
  EXPECT_EQ(n, good + bad);
  EXPECT_GE(good, 196);
  EXPECT_EQ(bad, 0);
}

TEST(FeatureMatcher, SearchByDescriptorIgnoresDynamicKeypoints) {
  Scene sc(100);
  const View v1 = sc.view(sc.pose1, true, 0);
  View v2 = sc.view(sc.pose2, true, 0);
  for (std::size_t k = 0; k < v2.fs->size(); k += 4) v2.fs->dynamic[k] = 1;
  Map map;
  std::vector<MapPoint*> pts;
  KeyFrame* kf = keyFrameWithPoints(map, sc, v1, sc.pose1, &pts);
  Frame cur(1, 1, 0.03, v2.fs);
  FeatureMatcher m;
  const int n = m.searchByDescriptor(*kf, cur);
  EXPECT_EQ(n, 75);
  for (std::size_t k = 0; k < v2.fs->size(); k += 4) EXPECT_EQ(cur.points[k], nullptr);
}

TEST(FeatureMatcher, SearchForTriangulationFindsEpipolarPairs) {
  Scene sc(200);
  const View v1 = sc.view(sc.pose1, false, 50);  // no depth: candidates for triangulation
  View v2 = sc.view(sc.pose2, false, 50);
  // A deliberately wrong pair: scene point `moved` keeps its descriptor in
  // view 2 but its keypoint is shifted 40 px across the (nearly horizontal)
  // epipolar lines, so the only keypoint with its descriptor violates the
  // epipolar constraint.
  const int moved = 17;
  const int kmoved = v2.key_of_point[moved];
  v2.fs->keys[kmoved].pt.y += 40.f;
  v2.fs->keys_un[kmoved].pt.y += 40.f;
  v2.fs->finalize(cv::Mat());  // rebuild the grid
  ASSERT_GT(
      epipolarDistance(sc, v1.fs->keys_un[v1.key_of_point[moved]].pt, v2.fs->keys_un[kmoved].pt),
      20.0);

  Map map;
  KeyFrame* k1 = map.createKeyFrame(0, 0.0, 0, v1.fs, sc.pose1);
  KeyFrame* k2 = map.createKeyFrame(1, 0.1, 1, v2.fs, sc.pose2);
  FeatureMatcher m;
  const auto pairs = m.searchForTriangulation(*k1, *k2);
  int good = 0, bad = 0;
  std::set<int> used1, used2;
  for (const auto& [i, j] : pairs) {
    EXPECT_TRUE(used1.insert(i).second) << "keypoint " << i << " of k1 used twice";
    EXPECT_TRUE(used2.insert(j).second) << "keypoint " << j << " of k2 used twice";
    EXPECT_LT(epipolarDistance(sc, v1.fs->keys_un[i].pt, v2.fs->keys_un[j].pt), 2.0);
    const int s = v1.point_of_key[i];
    if (s >= 0 && s == v2.point_of_key[j])
      ++good;
    else
      ++bad;
    EXPECT_NE(s, moved);
  }
  RecordProperty("correct_pairs", good);
  EXPECT_GE(good, 190);  // 199 findable
  EXPECT_EQ(bad, 0);
}

// Keypoints with a close (reliable) depth are left out: they already made map
// points from depth. Keypoints already holding a map point are left out too.
TEST(FeatureMatcher, SearchForTriangulationSkipsCloseDepthAndMatchedKeypoints) {
  Scene sc(100);
  const View v1 = sc.view(sc.pose1, false, 0);
  const View v2 = sc.view(sc.pose2, false, 0);
  Map map;
  KeyFrame* k1 = map.createKeyFrame(0, 0.0, 0, v1.fs, sc.pose1);
  KeyFrame* k2 = map.createKeyFrame(1, 0.1, 1, v2.fs, sc.pose2);
  // Scene points 0..9: close depth in view 1; 10..19: a map point in view 2.
  for (int s = 0; s < 10; ++s) v1.fs->depth[v1.key_of_point[s]] = 1.0f;
  MapPoint* mp = map.createMapPoint({0, 0, 1}, k2);
  for (int s = 10; s < 20; ++s) k2->addPoint(mp, v2.key_of_point[s]);
  FeatureMatcher m;
  const auto pairs = m.searchForTriangulation(*k1, *k2);
  std::set<int> found;
  for (const auto& [i, j] : pairs) {
    EXPECT_EQ(v1.point_of_key[i], v2.point_of_key[j]);
    found.insert(v1.point_of_key[i]);
  }
  for (int s = 0; s < 20; ++s) EXPECT_EQ(found.count(s), 0u) << s;
  RecordProperty("pairs", static_cast<int>(found.size()));
  EXPECT_GE(found.size(), 75u);
}

TEST(FeatureMatcher, FuseMergesDuplicatesAndFillsFreeKeypoints) {
  Scene sc(100);
  const View v1 = sc.view(sc.pose1, true, 20);
  const View v2 = sc.view(sc.pose2, true, 20);
  const View v3 = sc.view(CameraPose(CPose3D(-0.2, 0, 0.05, -0.05, 0, 0)), true, 0);
  Map map;
  std::vector<MapPoint*> pts;
  KeyFrame* ka = keyFrameWithPoints(map, sc, v1, sc.pose1, &pts);
  KeyFrame* kb = map.createKeyFrame(1, 0.1, 1, v2.fs, sc.pose2);
  KeyFrame* kc =
      map.createKeyFrame(2, 0.2, 2, v3.fs, CameraPose(CPose3D(-0.2, 0, 0.05, -0.05, 0, 0)));

  // Scene point 3: a duplicate map point seen only by kb (1 observation, as
  // many as ka's): the projected point survives.
  const int s_dup1 = 3;
  MapPoint* dup1 = map.createMapPoint(sc.points[s_dup1] + Eigen::Vector3d(0.001, 0, 0), kb);
  dup1->addObservation(kb, v2.key_of_point[s_dup1]);
  kb->addPoint(dup1, v2.key_of_point[s_dup1]);
  // Scene point 5: a duplicate seen by kb and kc (2 observations): it
  // survives and takes ka's observation.
  const int s_dup2 = 5;
  MapPoint* dup2 = map.createMapPoint(sc.points[s_dup2], kb);
  dup2->addObservation(kb, v2.key_of_point[s_dup2]);
  kb->addPoint(dup2, v2.key_of_point[s_dup2]);
  dup2->addObservation(kc, v3.key_of_point[s_dup2]);
  kc->addPoint(dup2, v3.key_of_point[s_dup2]);
  dup1->updateDescriptor();
  dup2->updateDescriptor();

  FeatureMatcher m;
  const int n = m.fuse(kb, pts);
  RecordProperty("fused", n);
  EXPECT_GE(n, 95);

  // Duplicate 1 merged into ka's point, which has both observations.
  MapPoint* p3 = pts[s_dup1];
  EXPECT_TRUE(dup1->bad);
  EXPECT_EQ(dup1->live(), p3);
  EXPECT_FALSE(p3->bad);
  EXPECT_EQ(p3->nObs(), 2);
  EXPECT_EQ(p3->obs.at(ka), v1.key_of_point[s_dup1]);
  EXPECT_EQ(p3->obs.at(kb), v2.key_of_point[s_dup1]);
  EXPECT_EQ(kb->points[v2.key_of_point[s_dup1]], p3);

  // Duplicate 2 had more observations: it survives with all three.
  MapPoint* p5 = pts[s_dup2];
  EXPECT_TRUE(p5->bad);
  EXPECT_EQ(p5->live(), dup2);
  EXPECT_FALSE(dup2->bad);
  EXPECT_EQ(dup2->nObs(), 3);
  EXPECT_EQ(dup2->obs.at(ka), v1.key_of_point[s_dup2]);
  EXPECT_EQ(ka->points[v1.key_of_point[s_dup2]], dup2);
  EXPECT_EQ(kb->points[v2.key_of_point[s_dup2]], dup2);

  // A free keypoint: a new observation at the right keypoint.
  int filled = 0;
  for (std::size_t s = 0; s < sc.points.size(); ++s) {
    if (static_cast<int>(s) == s_dup1 || static_cast<int>(s) == s_dup2) continue;
    MapPoint* p = pts[s];
    ASSERT_FALSE(p->bad);
    if (!p->isInKeyFrame(kb)) continue;
    ++filled;
    EXPECT_EQ(p->obs.at(kb), v2.key_of_point[s]) << "scene point " << s;
    EXPECT_EQ(kb->points[v2.key_of_point[s]], p);
  }
  EXPECT_GE(filled, 93);
  // Distractors stay free.
  for (std::size_t k = 0; k < kb->points.size(); ++k)
    if (v2.point_of_key[k] < 0) {
      EXPECT_EQ(kb->points[k], nullptr);
    }

  // A second fuse finds nothing new to do for points already in kb.
  for (MapPoint*& p : pts) p = p->live();
  EXPECT_EQ(m.fuse(kb, pts), 0);
}

TEST(RotationHistogram, KeepsDominantBinDiscardsOutliers) {
  RotationHistogram h;
  for (int i = 0; i < 20; ++i) h.add(30.f + 10.f + 0.1f * i, 30.f, i);  // ~10 deg
  h.add(100.f, 0.f, 100);                                               // 100 deg
  h.add(0.f, 160.f, 101);                                               // -160 = 200 deg
  h.add(300.f, 0.f, 102);                                               // 300 deg
  auto out = h.outliers();
  std::sort(out.begin(), out.end());
  EXPECT_EQ(out, (std::vector<int>{100, 101, 102}));
}

TEST(RotationHistogram, KeepsUpToThreeSignificantBins) {
  RotationHistogram h;
  int id = 0;
  for (int i = 0; i < 20; ++i) h.add(10.f, 0.f, id++);  // 0..19 at 10 deg
  for (int i = 0; i < 5; ++i) h.add(60.f, 0.f, id++);   // 20..24 at 60 deg: >= 10 % of 20
  for (int i = 0; i < 3; ++i) h.add(0.f, 90.f, id++);   // 25..27 at 270 deg: >= 10 %
  for (int i = 0; i < 2; ++i) h.add(180.f, 0.f, id++);  // 28..29: fourth bin, dropped
  h.add(0.f, 200.f, 30);                                // 160 deg: single, dropped
  auto out = h.outliers();
  std::sort(out.begin(), out.end());
  EXPECT_EQ(out, (std::vector<int>{28, 29, 30}));
}

TEST(RotationHistogram, SmallBinsBelowTenPercentDropped) {
  RotationHistogram h;
  for (int i = 0; i < 30; ++i) h.add(5.f, 0.f, i);
  h.add(90.f, 0.f, 30);  // 1 < 10 % of 30
  h.add(91.f, 0.f, 31);  // same bin: 2 < 3
  auto out = h.outliers();
  std::sort(out.begin(), out.end());
  EXPECT_EQ(out, (std::vector<int>{30, 31}));
}

// +3 deg and -3 deg (= 357 deg) are the same small rotation: wrap-around.
TEST(RotationHistogram, WrapsAroundZero) {
  RotationHistogram h;
  for (int i = 0; i < 10; ++i) h.add(3.f, 0.f, i);
  for (int i = 10; i < 20; ++i) h.add(0.f, 3.f, i);
  h.add(180.f, 0.f, 20);
  EXPECT_EQ(h.outliers(), std::vector<int>{20});
}

TEST(RotationHistogram, EmptyHasNoOutliers) {
  RotationHistogram h;
  EXPECT_TRUE(h.outliers().empty());
}
