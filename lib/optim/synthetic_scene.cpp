#include "optim/synthetic_scene.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

#include "optim/se3_math.h"

namespace dynslam::optim {
namespace {

constexpr double kWidth = 640, kHeight = 480;

Eigen::Vector3d randomUnit(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Vector3d v;
  do {
    v = Eigen::Vector3d(n(rng), n(rng), n(rng));
  } while (v.norm() < 1e-6);
  return v.normalized();
}

bool inImage(const Eigen::Vector2d& px) {
  return px.x() >= 0 && px.x() < kWidth && px.y() >= 0 && px.y() < kHeight;
}

/// Camera at `centre` looking at `target`, image y axis roughly along world +y.
mrpt::poses::CPose3D lookAt(const Eigen::Vector3d& centre, const Eigen::Vector3d& target) {
  Rigid T;
  const Eigen::Vector3d z = (target - centre).normalized();
  const Eigen::Vector3d x = Eigen::Vector3d::UnitY().cross(z).normalized();
  T.R.col(0) = x;
  T.R.col(1) = z.cross(x);
  T.R.col(2) = z;
  T.t = centre;
  return toPose(T);
}

/// The observation of a camera-frame point, with noise; depth optional.
BAObservation observe(const ProjectionModel& cam, const Eigen::Vector3d& pc, bool depth,
                      double sigma, std::mt19937& rng) {
  std::normal_distribution<double> noise(0.0, sigma);
  BAObservation o;
  const Eigen::Vector3d s = cam.projectStereo(pc);
  o.pixel = Eigen::Vector2d(s.x() + noise(rng), s.y() + noise(rng));
  o.ur = depth ? s.z() + noise(rng) : -1.0;
  o.inv_sigma2 = 1.0 / (sigma * sigma);
  return o;
}

}  // namespace

ProjectionModel syntheticCamera() {
  ProjectionModel cam;
  cam.fx = cam.fy = 517.0;
  cam.cx = 318.0;
  cam.cy = 255.0;
  cam.bf = 40.0;
  return cam;
}

PoseScene makePoseScene(const ProjectionModel& cam, const PoseSceneParams& p) {
  std::mt19937 rng(p.seed);
  std::uniform_real_distribution<double> U(0.0, kWidth), V(0.0, kHeight);
  std::uniform_real_distribution<double> Z(p.min_depth, p.max_depth);
  PoseScene s;
  s.true_wc = mrpt::poses::CPose3D(0.3, -0.2, 1.1, 0.4, -0.2, 0.1);
  const Rigid T_wc = toRigid(s.true_wc);

  std::vector<int> order(p.observations);
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin(), order.end(), rng);
  s.is_outlier.assign(p.observations, false);
  const int n_out = static_cast<int>(std::lround(p.outlier_fraction * p.observations));
  for (int i = 0; i < n_out; ++i) s.is_outlier[order[i]] = true;

  for (int i = 0; i < p.observations; ++i) {
    const Eigen::Vector3d pc = cam.unproject(U(rng), V(rng), Z(rng));
    const BAObservation o = s.is_outlier[i] ? observe(cam, cam.unproject(U(rng), V(rng), Z(rng)),
                                                      p.with_depth, p.pixel_sigma, rng)
                                            : observe(cam, pc, p.with_depth, p.pixel_sigma, rng);
    PoseObservation po;
    po.point_world = T_wc * pc;
    po.pixel = o.pixel;
    po.ur = o.ur;
    po.inv_sigma2 = o.inv_sigma2;
    s.obs.push_back(po);
  }
  return s;
}

BAScene makeBAScene(const ProjectionModel& cam, const BASceneParams& p) {
  std::mt19937 rng(p.seed);
  BAScene s;
  BAProblem& t = s.truth;
  t.camera = cam;

  // Keyframes on an arc of radius 4 m (80 degrees), looking at the origin.
  for (int k = 0; k < p.keyframes; ++k) {
    const double a = p.keyframes > 1 ? -0.7 + 1.4 * k / (p.keyframes - 1) : 0.0;
    const Eigen::Vector3d c(4.0 * std::sin(a), 0.3 * std::sin(3.0 * a), -4.0 * std::cos(a));
    BAKeyframe kf;
    kf.pose_wc = lookAt(c, Eigen::Vector3d::Zero());
    kf.fixed = k < p.fixed_keyframes;
    t.keyframes.push_back(kf);
  }
  std::vector<Rigid> T_cw;
  for (const auto& kf : t.keyframes) T_cw.push_back(toRigid(-kf.pose_wc));

  // Points in a 2 m cube; each seen by a random subset of the keyframes that
  // see it, sized so that the total is close to p.observations.
  std::uniform_real_distribution<double> cube(-1.0, 1.0), unit(0.0, 1.0);
  const double per_point = static_cast<double>(p.observations) / std::max(1, p.points);
  for (int j = 0; j < p.points; ++j) {
    BAPoint pt;
    pt.position = Eigen::Vector3d(cube(rng), cube(rng), cube(rng));
    std::vector<int> visible;
    for (int k = 0; k < p.keyframes; ++k) {
      const Eigen::Vector3d pc = T_cw[k] * pt.position;
      if (pc.z() > 0.1 && inImage(cam.project(pc))) visible.push_back(k);
    }
    std::shuffle(visible.begin(), visible.end(), rng);
    const int want = static_cast<int>(std::floor(per_point + unit(rng)));  // unbiased rounding
    const int n = std::min<int>(static_cast<int>(visible.size()), std::max(2, want));
    for (int m = 0; m < n; ++m) {
      const int k = visible[m];
      BAObservation o =
          observe(cam, T_cw[k] * pt.position, unit(rng) < p.depth_fraction, p.pixel_sigma, rng);
      o.keyframe = k;
      o.point = j;
      t.observations.push_back(o);
    }
    t.points.push_back(pt);
  }

  // Gross outliers: distinct observations shifted by 20-60 px.
  s.is_outlier.assign(t.observations.size(), false);
  std::vector<int> order(t.observations.size());
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin(), order.end(), rng);
  std::uniform_real_distribution<double> shift(20.0, 60.0), angle(0.0, 2.0 * M_PI);
  for (int i = 0; i < std::min<int>(p.gross_outliers, static_cast<int>(order.size())); ++i) {
    BAObservation& o = t.observations[order[i]];
    const double d = shift(rng), a = angle(rng);
    o.pixel += d * Eigen::Vector2d(std::cos(a), std::sin(a));
    if (o.ur >= 0) o.ur += d * std::cos(a);
    s.is_outlier[order[i]] = true;
  }

  // Initial estimate: free poses and all points perturbed.
  s.initial = t;
  for (std::size_t k = 0; k < s.initial.keyframes.size(); ++k) {
    auto& kf = s.initial.keyframes[k];
    if (!kf.fixed) {
      kf.pose_wc = perturbPose(kf.pose_wc, p.pose_noise_m, p.pose_noise_rad, rng());
    }
  }
  std::normal_distribution<double> pn(0.0, p.point_noise_m);
  for (auto& pt : s.initial.points) pt.position += Eigen::Vector3d(pn(rng), pn(rng), pn(rng));
  return s;
}

double translationError(const mrpt::poses::CPose3D& a, const mrpt::poses::CPose3D& b) {
  return (toRigid(a).t - toRigid(b).t).norm();
}

double rotationError(const mrpt::poses::CPose3D& a, const mrpt::poses::CPose3D& b) {
  const Eigen::Matrix3d d = toRigid(a).R.transpose() * toRigid(b).R;
  return Eigen::AngleAxisd(d).angle();
}

mrpt::poses::CPose3D perturbPose(const mrpt::poses::CPose3D& a, double meters, double radians,
                                 std::uint32_t seed) {
  std::mt19937 rng(seed);
  Rigid T = toRigid(a);
  T.t += meters * randomUnit(rng);
  T.R = T.R * quaternionExp(radians * randomUnit(rng)).toRotationMatrix();
  return toPose(T);
}

}  // namespace dynslam::optim
