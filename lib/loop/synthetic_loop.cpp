#include "loop/synthetic_loop.h"

#include <cmath>
#include <random>

namespace dynslam::loop {

namespace {

/// Camera at angle th on the circle, looking radially out, image y down
/// (world z up).
mrpt::poses::CPose3D circlePose(double r, double th) {
  const Eigen::Vector3d z(std::cos(th), std::sin(th), 0), y(0, 0, -1);
  Eigen::Matrix3d R;
  R << y.cross(z), y, z;
  return mrpt::poses::CPose3D::FromRotationAndTranslation(
      R, Eigen::Vector3d(r * std::cos(th), r * std::sin(th), 0));
}

}  // namespace

SyntheticLoop buildSyntheticLoop(Map& map, const SyntheticLoopParams& p) {
  SyntheticLoop s;
  s.ctx = idealFrameContext();
  const FrameContext& ctx = *s.ctx;
  std::mt19937 rng(p.seed);
  std::uniform_real_distribution<double> u01(0, 1);
  std::normal_distribution<double> px_noise(0, p.pixel_noise);

  const int nl = p.landmarks;
  cv::Mat lm_desc(nl, 32, CV_8UC1);
  cv::randu(lm_desc, 0, 256);
  std::vector<int> lm_octave(nl);
  for (int i = 0; i < nl; ++i) {
    const double a = 2 * M_PI * u01(rng);
    s.landmarks.emplace_back(p.wall_radius * std::cos(a), p.wall_radius * std::sin(a),
                             (u01(rng) - 0.5) * p.wall_height);
    lm_octave[i] = static_cast<int>(u01(rng) * 3);  // levels 0..2
  }

  const mrpt::poses::CPose3D drift(p.step_drift.x(), p.step_drift.y(), p.step_drift.z(), 0,
                                   p.yaw_drift_deg * M_PI / 180.0, 0);  // about camera y = vertical
  std::vector<MapPoint*> active(nl, nullptr);  // landmark -> its current map point
  std::vector<long> last_seen(nl, -1000);
  mrpt::poses::CPose3D est;
  for (int k = 0; k < p.keyframes; ++k) {
    const mrpt::poses::CPose3D truth = circlePose(p.radius, 2 * M_PI * k / p.keyframes);
    if (k == 0)
      est = truth;
    else
      est = est + (truth - s.truth.back()) + drift;
    s.truth.push_back(truth);
    const CameraPose tp(truth);

    auto fs = std::make_shared<FeatureSet>();
    fs->ctx = s.ctx;
    std::vector<int> lms;
    std::vector<double> depths;
    for (int i = 0; i < nl; ++i) {
      const Eigen::Vector3d pc = tp.toCamera(s.landmarks[i]);
      if (pc.z() < 0.5) continue;
      const Eigen::Vector2d uv = ctx.proj.project(pc);
      if (uv.x() < 10 || uv.y() < 10 || uv.x() > 630 || uv.y() > 470) continue;
      fs->keys.emplace_back(static_cast<float>(uv.x() + px_noise(rng)),
                            static_cast<float>(uv.y() + px_noise(rng)), 31.f, 0.f, 0.f,
                            lm_octave[i]);
      lms.push_back(i);
      depths.push_back(pc.z());
    }
    fs->descriptors = cv::Mat(static_cast<int>(lms.size()), 32, CV_8UC1);
    for (std::size_t j = 0; j < lms.size(); ++j)
      lm_desc.row(lms[j]).copyTo(fs->descriptors.row(static_cast<int>(j)));
    fs->finalize(cv::Mat());
    for (std::size_t j = 0; j < lms.size(); ++j) {  // RGB-D depth at each keypoint
      fs->depth[j] = static_cast<float>(depths[j]);
      fs->ur[j] = static_cast<float>(fs->keys_un[j].pt.x - ctx.proj.bf / depths[j]);
    }

    KeyFrame* kf = map.createKeyFrame(k, 0.1 * k, k, fs, CameraPose(est));
    s.kfs.push_back(kf);
    s.keypoint_landmark.push_back(lms);
    for (std::size_t j = 0; j < lms.size(); ++j) {
      const int i = lms[j];
      MapPoint* mp = active[i];
      if (!mp || mp->bad || k - last_seen[i] > p.reobserve_gap) {
        // A new point from this keyframe's measurement and (drifted) pose.
        mp = map.createMapPoint(kf->pose.toWorld(fs->unprojectCamera(j)), kf);
        active[i] = mp;
        s.landmark_of[mp] = i;
      }
      mp->addObservation(kf, static_cast<int>(j));
      kf->addPoint(mp, static_cast<int>(j));
      last_seen[i] = k;
    }
    for (MapPoint* mp : kf->livePoints()) mp->updateDescriptor();
    kf->updateConnections();
  }
  for (MapPoint* mp : map.mapPoints()) mp->updateNormalAndDepth();
  return s;
}

void SyntheticLoop::correspondences(int a, int b, std::vector<PointCorrespondence>& out,
                                    std::vector<std::pair<int, MapPoint*>>& matches) const {
  out.clear();
  matches.clear();
  const KeyFrame* ka = kfs[a];
  const KeyFrame* kb = kfs[b];
  std::map<int, MapPoint*> a_points;  // landmark -> a's map point
  for (std::size_t j = 0; j < ka->points.size(); ++j)
    if (ka->points[j] && !ka->points[j]->bad) a_points[keypoint_landmark[a][j]] = ka->points[j];
  std::map<int, int> a_keypoint;
  for (std::size_t j = 0; j < keypoint_landmark[a].size(); ++j)
    a_keypoint[keypoint_landmark[a][j]] = static_cast<int>(j);
  const FeatureSet& fb = kb->f();
  for (std::size_t j = 0; j < fb.size(); ++j) {
    auto it = a_points.find(keypoint_landmark[b][j]);
    if (it == a_points.end() || fb.depth[j] <= 0) continue;
    const int ja = a_keypoint.at(it->first);
    PointCorrespondence c;
    c.pa = ka->pose.toCamera(it->second->pos);
    c.pb = fb.unprojectCamera(j);
    c.uva = Eigen::Vector2d(ka->f().keys_un[ja].pt.x, ka->f().keys_un[ja].pt.y);
    c.uvb = Eigen::Vector2d(fb.keys_un[j].pt.x, fb.keys_un[j].pt.y);
    c.sigma2_a = ctx->sigma2[ka->f().keys_un[ja].octave];
    c.sigma2_b = ctx->sigma2[fb.keys_un[j].octave];
    out.push_back(c);
    matches.emplace_back(static_cast<int>(j), it->second);
  }
}

void SyntheticLoop::keyframeError(double& max_err, double& rms) const {
  max_err = rms = 0;
  for (std::size_t k = 0; k < kfs.size(); ++k) {
    const double e = (kfs[k]->pose.center() - CameraPose(truth[k]).center()).norm();
    max_err = std::max(max_err, e);
    rms += e * e;
  }
  rms = std::sqrt(rms / std::max<std::size_t>(1, kfs.size()));
}

void SyntheticLoop::pointError(const Map& map, double& max_err, double& rms) const {
  max_err = rms = 0;
  int n = 0;
  for (const MapPoint* mp : map.mapPoints()) {
    auto it = landmark_of.find(mp);
    if (it == landmark_of.end()) continue;
    const double e = (mp->pos - landmarks[it->second]).norm();
    max_err = std::max(max_err, e);
    rms += e * e;
    ++n;
  }
  rms = std::sqrt(rms / std::max(1, n));
}

}  // namespace dynslam::loop
