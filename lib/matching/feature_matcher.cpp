#include "matching/feature_matcher.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include <Eigen/Dense>

#include "core/log.h"
#include "features/orb_extractor.h"

namespace dynslam {

void RotationHistogram::add(float a1, float a2, int idx) {
  float rot = a1 - a2;
  if (rot < 0) rot += 360.f;
  int bin = static_cast<int>(std::round(rot * kBins / 360.f));
  if (bin == kBins) bin = 0;
  bins_[std::clamp(bin, 0, kBins - 1)].push_back(idx);
}

std::vector<int> RotationHistogram::outliers() const {
  int m1 = 0, m2 = 0, m3 = 0;
  int i1 = -1, i2 = -1, i3 = -1;
  for (int i = 0; i < kBins; ++i) {
    const int s = static_cast<int>(bins_[i].size());
    if (s > m1) {
      m3 = m2;
      i3 = i2;
      m2 = m1;
      i2 = i1;
      m1 = s;
      i1 = i;
    } else if (s > m2) {
      m3 = m2;
      i3 = i2;
      m2 = s;
      i2 = i;
    } else if (s > m3) {
      m3 = s;
      i3 = i;
    }
  }
  if (m2 < 0.1 * m1) i2 = -1;
  if (m3 < 0.1 * m1) i3 = -1;
  std::vector<int> out;
  for (int i = 0; i < kBins; ++i)
    if (i != i1 && i != i2 && i != i3) out.insert(out.end(), bins_[i].begin(), bins_[i].end());
  return out;
}

int FeatureMatcher::searchByProjection(Frame& cur, const Frame& last, float th) const {
  const FeatureSet& cf = cur.f();
  const FrameContext& ctx = *cf.ctx;
  RotationHistogram hist;
  int n = 0;
  for (std::size_t i = 0; i < last.points.size(); ++i) {
    MapPoint* mp = last.points[i];
    if (!mp || mp->bad || last.outlier[i]) continue;
    const Eigen::Vector3d pc = cur.pose.toCamera(mp->pos);
    if (pc.z() <= 0) continue;
    const Eigen::Vector3d uvr = ctx.proj.projectStereo(pc);
    if (!ctx.inImage(uvr.x(), uvr.y())) continue;
    const int last_level = last.f().keys_un[i].octave;
    const float radius = th * ctx.scale[last_level];
    const auto cand =
        cf.featuresInArea(static_cast<float>(uvr.x()), static_cast<float>(uvr.y()), radius,
                          std::max(0, last_level - 1), std::min(ctx.levels - 1, last_level + 1));
    if (cand.empty()) continue;
    const uint8_t* d = mp->descriptor.ptr<uint8_t>();
    int best = INT_MAX, best_idx = -1;
    for (int j : cand) {
      if (cur.points[j] && cur.points[j]->nObs() > 0) continue;
      if (cf.ur[j] >= 0 && std::abs(uvr.z() - cf.ur[j]) > radius) continue;
      const int dist = descriptorDistance(d, cf.descriptor(j));
      if (dist < best) {
        best = dist;
        best_idx = j;
      }
    }
    if (best <= p_.th_high) {
      cur.points[best_idx] = mp;
      ++n;
      hist.add(last.f().keys_un[i].angle, cf.keys_un[best_idx].angle, best_idx);
    }
  }
  for (int j : hist.outliers()) {
    cur.points[j] = nullptr;
    --n;
  }
  return n;
}

int FeatureMatcher::searchByProjection(Frame& cur, const std::vector<MapPoint*>& points,
                                       float th) const {
  const FeatureSet& cf = cur.f();
  const FrameContext& ctx = *cf.ctx;
  int n = 0;
  int no_cand = 0, too_far = 0, ratio_fail = 0, all_taken = 0;
  for (MapPoint* mp : points) {
    if (!mp->track_in_view || mp->bad) continue;
    const int level = mp->pred_level;
    const float r = th * (mp->view_cos > 0.998f ? 2.5f : 4.0f) * ctx.scale[level];
    const auto cand = cf.featuresInArea(mp->proj_x, mp->proj_y, r, level - 1, level);
    if (cand.empty()) {
      ++no_cand;
      continue;
    }
    const uint8_t* d = mp->descriptor.ptr<uint8_t>();
    int best = INT_MAX, second = INT_MAX, best_idx = -1, best_level = -1, second_level = -1;
    int free = 0;
    for (int j : cand) {
      if (cur.points[j] && cur.points[j]->nObs() > 0) continue;
      ++free;
      if (cf.ur[j] >= 0 && std::abs(mp->proj_ur - cf.ur[j]) > r) continue;
      const int dist = descriptorDistance(d, cf.descriptor(j));
      if (dist < best) {
        second = best;
        second_level = best_level;
        best = dist;
        best_level = cf.keys_un[j].octave;
        best_idx = j;
      } else if (dist < second) {
        second = dist;
        second_level = cf.keys_un[j].octave;
      }
    }
    if (free == 0) {
      ++all_taken;
      continue;
    }
    if (best > p_.th_high) {
      ++too_far;
      continue;
    }
    if (best_level == second_level && best > p_.nn_ratio * second) {
      ++ratio_fail;
      continue;
    }
    cur.points[best_idx] = mp;
    ++n;
  }
  logf(LogLevel::kTrace, "match",
       "local: %d matched, %d no candidate, %d all taken, %d descriptor too far, %d ratio", n,
       no_cand, all_taken, too_far, ratio_fail);
  return n;
}

int FeatureMatcher::searchByDescriptor(const KeyFrame& kf, Frame& cur) const {
  const FeatureSet& kff = kf.f();
  const FeatureSet& cf = cur.f();
  // Candidate lists: keyframe keypoints with live map points, static frame keypoints.
  std::vector<int> kidx, cidx;
  for (std::size_t i = 0; i < kf.points.size(); ++i)
    if (kf.points[i] && !kf.points[i]->bad) kidx.push_back(static_cast<int>(i));
  for (std::size_t j = 0; j < cf.size(); ++j)
    if (!cf.dynamic[j]) cidx.push_back(static_cast<int>(j));
  RotationHistogram hist;
  int n = 0;
  std::vector<int> best_for_frame(cf.size(), INT_MAX);
  for (int i : kidx) {
    const uint8_t* d = kff.descriptor(i);
    int best = INT_MAX, second = INT_MAX, best_j = -1;
    for (int j : cidx) {
      const int dist = descriptorDistance(d, cf.descriptor(j));
      if (dist < best) {
        second = best;
        best = dist;
        best_j = j;
      } else if (dist < second) {
        second = dist;
      }
    }
    if (best_j < 0 || best > p_.th_low || best > 0.7f * second) continue;
    if (cur.points[best_j]) {
      if (best >= best_for_frame[best_j]) continue;
      --n;  // replaced below
    }
    best_for_frame[best_j] = best;
    cur.points[best_j] = kf.points[i];
    ++n;
    hist.add(kff.keys_un[i].angle, cf.keys_un[best_j].angle, best_j);
  }
  for (int j : hist.outliers()) {
    if (cur.points[j]) {
      cur.points[j] = nullptr;
      --n;
    }
  }
  return n;
}

std::vector<std::pair<int, int>> FeatureMatcher::searchForTriangulation(const KeyFrame& k1,
                                                                        const KeyFrame& k2) const {
  const FeatureSet& f1 = k1.f();
  const FeatureSet& f2 = k2.f();
  const FrameContext& ctx = *f1.ctx;
  // Fundamental matrix F12 (x1^T F12 x2 = 0) from the relative pose.
  const Eigen::Matrix3d R12 = k1.pose.Rcw() * k2.pose.Rwc();
  const Eigen::Vector3d t12 = k1.pose.Rcw() * (k2.pose.center() - k1.pose.center());
  Eigen::Matrix3d tx;
  tx << 0, -t12.z(), t12.y(), t12.z(), 0, -t12.x(), -t12.y(), t12.x(), 0;
  const Eigen::Matrix3d Kinv = ctx.proj.matrix().inverse();
  const Eigen::Matrix3d F12 = Kinv.transpose() * tx * R12 * Kinv;
  // Epipole of k1's centre in k2: too-close matches give poor parallax.
  const Eigen::Vector3d c1_in_2 = k2.pose.toCamera(k1.pose.center());
  const Eigen::Vector2d ep = ctx.proj.project(c1_in_2);

  std::vector<int> free2;
  for (std::size_t j = 0; j < f2.size(); ++j)
    if (!k2.points[j] && !f2.dynamic[j]) free2.push_back(static_cast<int>(j));
  std::vector<int> taken2(f2.size(), -1);
  std::vector<int> dist2(f2.size(), INT_MAX);
  std::vector<int> match1(f1.size(), -1);
  RotationHistogram hist;
  for (std::size_t i = 0; i < f1.size(); ++i) {
    // Labelled unsure (FeatureSet::unsure): no new point from k1's side.
    if (k1.points[i] || f1.dynamic[i] || f1.isUnsure(i)) continue;
    // RGB-D: keypoints with a reliable depth already made map points.
    if (f1.depth[i] > 0 && f1.depth[i] < ctx.close_depth) continue;
    const cv::KeyPoint& kp1 = f1.keys_un[i];
    const Eigen::Vector3d x1(kp1.pt.x, kp1.pt.y, 1.0);
    const Eigen::Vector3d line = F12.transpose() * x1;  // line in image 2
    const double den = line.x() * line.x() + line.y() * line.y();
    if (den <= 0) continue;
    const uint8_t* d1 = f1.descriptor(i);
    int best = p_.th_low + 1, best_j = -1;
    for (int j : free2) {
      if (f2.depth[j] > 0 && f2.depth[j] < ctx.close_depth) continue;
      const int dist = descriptorDistance(d1, f2.descriptor(j));
      if (dist >= best) continue;
      const cv::KeyPoint& kp2 = f2.keys_un[j];
      const double dx = ep.x() - kp2.pt.x, dy = ep.y() - kp2.pt.y;
      if (c1_in_2.z() > 0 && dx * dx + dy * dy < 100 * ctx.scale[kp2.octave]) continue;
      const double num = line.x() * kp2.pt.x + line.y() * kp2.pt.y + line.z();
      if (num * num / den >= 3.84 * ctx.sigma2[kp2.octave]) continue;
      best = dist;
      best_j = j;
    }
    if (best_j < 0) continue;
    if (taken2[best_j] >= 0) {
      if (best >= dist2[best_j]) continue;
      match1[taken2[best_j]] = -1;
    }
    taken2[best_j] = static_cast<int>(i);
    dist2[best_j] = best;
    match1[i] = best_j;
    hist.add(kp1.angle, f2.keys_un[best_j].angle, static_cast<int>(i));
  }
  for (int i : hist.outliers()) match1[i] = -1;
  std::vector<std::pair<int, int>> pairs;
  for (std::size_t i = 0; i < match1.size(); ++i)
    if (match1[i] >= 0) pairs.emplace_back(static_cast<int>(i), match1[i]);
  return pairs;
}

int FeatureMatcher::fuse(KeyFrame* kf, const std::vector<MapPoint*>& points, float th) const {
  const FeatureSet& f = kf->f();
  const FrameContext& ctx = *f.ctx;
  int n = 0;
  for (MapPoint* mp : points) {
    if (!mp || mp->bad || mp->isInKeyFrame(kf)) continue;
    const Eigen::Vector3d pc = kf->pose.toCamera(mp->pos);
    if (pc.z() <= 0) continue;
    const Eigen::Vector3d uvr = ctx.proj.projectStereo(pc);
    if (!ctx.inImage(uvr.x(), uvr.y())) continue;
    const Eigen::Vector3d po = mp->pos - kf->pose.center();
    const double dist = po.norm();
    if (dist < 0.8 * mp->min_dist || dist > 1.2 * mp->max_dist) continue;
    if (po.dot(mp->normal) < 0.5 * dist) continue;
    const int level = mp->predictScale(dist, ctx);
    const float r = th * ctx.scale[level];
    const auto cand = f.featuresInArea(static_cast<float>(uvr.x()), static_cast<float>(uvr.y()), r);
    const uint8_t* d = mp->descriptor.ptr<uint8_t>();
    int best = INT_MAX, best_j = -1;
    for (int j : cand) {
      const cv::KeyPoint& kp = f.keys_un[j];
      if (kp.octave < level - 1 || kp.octave > level) continue;
      const double ex = uvr.x() - kp.pt.x, ey = uvr.y() - kp.pt.y;
      double e2 = ex * ex + ey * ey;
      double chi = 5.99;
      if (f.ur[j] >= 0) {
        const double er = uvr.z() - f.ur[j];
        e2 += er * er;
        chi = 7.8;
      }
      if (e2 * ctx.inv_sigma2[kp.octave] > chi) continue;
      const int dist_d = descriptorDistance(d, f.descriptor(j));
      if (dist_d < best) {
        best = dist_d;
        best_j = j;
      }
    }
    if (best > p_.th_low) continue;
    MapPoint* existing = kf->points[best_j];
    if (existing && !existing->bad) {
      if (existing->nObs() > mp->nObs())
        mp->replaceWith(existing);
      else
        existing->replaceWith(mp);
    } else {
      mp->addObservation(kf, best_j);
      kf->addPoint(mp, best_j);
    }
    ++n;
  }
  return n;
}

}  // namespace dynslam
