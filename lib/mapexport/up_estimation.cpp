#include "mapexport/up_estimation.h"

#include <pcl/console/print.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/sample_consensus/ransac.h>
#include <pcl/sample_consensus/sac_model_plane.h>
#include <pcl/search/kdtree.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <vector>

namespace dynslam {

UpEstimate estimateMapUp(const MapData& map, std::array<double, 3> fallback,
                         const UpEstimateOptions& options) {
  UpEstimate result;
  result.prior = estimateUpDirection(map.keyframes, fallback);
  result.up = result.prior;
  result.source = map.keyframes.empty() ? "fallback" : "keyframes";
  const Eigen::Vector3d prior =
      Eigen::Vector3d(result.prior[0], result.prior[1], result.prior[2]).normalized();

  // Evenly spaced subsample: deterministic, and enough for planes of a few
  // percent of the map.
  const std::size_t n_all = map.points.size();
  const std::size_t step = std::max<std::size_t>(
      1, (n_all + options.max_points - 1) / std::max<std::size_t>(1, options.max_points));
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  cloud->reserve(n_all / step + 1);
  for (std::size_t i = 0; i < n_all; i += step) {
    const auto& p = map.points[i];
    cloud->push_back(pcl::PointXYZ(p.x, p.y, p.z));
  }
  const std::size_t n = cloud->size();
  const std::size_t min_inliers =
      std::max<std::size_t>(10, std::size_t(options.min_plane_share * double(n)));
  if (n < min_inliers) return result;

  Eigen::Vector3d cameras = Eigen::Vector3d::Zero();
  for (const auto& kf : map.keyframes)
    cameras += Eigen::Vector3d(kf.pose.x(), kf.pose.y(), kf.pose.z());
  if (!map.keyframes.empty()) cameras /= double(map.keyframes.size());

  // PCL reports every collinear draw on the console; they are expected here.
  struct QuietPcl {
    pcl::console::VERBOSITY_LEVEL saved = pcl::console::getVerbosityLevel();
    QuietPcl() { pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS); }
    ~QuietPcl() { pcl::console::setVerbosityLevel(saved); }
  } quiet;

  pcl::Indices remaining(n);
  for (std::size_t i = 0; i < n; ++i) remaining[i] = pcl::index_t(i);
  const double cos_limit = std::cos(options.max_prior_angle_deg * M_PI / 180);
  std::size_t best_inliers = 0;
  for (int plane = 0; plane < options.max_planes && remaining.size() >= min_inliers; ++plane) {
    auto model = std::make_shared<pcl::SampleConsensusModelPlane<pcl::PointXYZ>>(cloud, remaining);
    // Draw each sample's three points within sample_radius of each other:
    // a plane holding a few percent of the map (the floor seen at the image
    // border) is then hit in a few dozen draws instead of thousands.
    auto tree = std::make_shared<pcl::search::KdTree<pcl::PointXYZ>>();
    tree->setInputCloud(cloud, std::make_shared<const pcl::Indices>(remaining));
    model->setSamplesMaxDist(options.sample_radius, tree);
    pcl::RandomSampleConsensus<pcl::PointXYZ> ransac(model, options.inlier_distance);
    ransac.setMaxIterations(options.max_iterations);
    if (!ransac.computeModel()) break;
    pcl::Indices inliers;
    ransac.getInliers(inliers);
    if (inliers.size() < min_inliers) break;
    Eigen::VectorXf coeff;
    ransac.getModelCoefficients(coeff);
    Eigen::VectorXf refined;
    model->optimizeModelCoefficients(inliers, coeff, refined);  // least squares on inliers
    if (refined.size() == 4 && std::isfinite(refined[0])) coeff = refined;
    Eigen::Vector3d normal(coeff[0], coeff[1], coeff[2]);
    double offset = coeff[3];
    const double norm = normal.norm();
    // Spread of the inliers within the plane (second principal axis).
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const auto i : inliers) mean += (*cloud)[i].getVector3fMap().cast<double>();
    mean /= double(inliers.size());
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (const auto i : inliers) {
      const Eigen::Vector3d d = (*cloud)[i].getVector3fMap().cast<double>() - mean;
      cov += d * d.transpose();
    }
    cov /= double(inliers.size());
    const double spread = std::sqrt(
        std::max(0.0, Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov, Eigen::EigenvaluesOnly)
                          .eigenvalues()(1)));
    if (norm > 1e-9 && spread >= options.min_plane_spread) {
      normal /= norm;
      offset /= norm;
      // Seen from the front: the cameras are on the positive side.
      const bool flip =
          map.keyframes.empty() ? normal.dot(prior) < 0 : normal.dot(cameras) + offset < 0;
      if (flip) normal = -normal;
      if (normal.dot(prior) >= cos_limit && inliers.size() > best_inliers) {
        best_inliers = inliers.size();
        result.up = {normal.x(), normal.y(), normal.z()};
        result.source = "plane";
        result.plane_share = double(inliers.size()) / double(n);
      }
    }
    // Remove this plane's inliers (both lists are sorted) and look for the next.
    std::sort(inliers.begin(), inliers.end());
    pcl::Indices rest;
    rest.reserve(remaining.size() - inliers.size());
    std::set_difference(remaining.begin(), remaining.end(), inliers.begin(), inliers.end(),
                        std::back_inserter(rest));
    remaining.swap(rest);
  }
  const Eigen::Vector3d up(result.up[0], result.up[1], result.up[2]);
  result.prior_angle_deg =
      std::acos(std::clamp(up.normalized().dot(prior), -1.0, 1.0)) * 180 / M_PI;
  return result;
}

void writeUpEstimateJson(JsonWriter& j, const UpEstimate& up) {
  j.beginObject("up")
      .value("source", up.source)
      .value("plane_share", up.plane_share)
      .value("angle_to_keyframe_estimate_deg", up.prior_angle_deg);
  j.beginArray("direction");
  for (double v : up.up) j.element(v);
  j.endArray().endObject();
}

}  // namespace dynslam
