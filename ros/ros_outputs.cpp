#include "ros/ros_outputs.h"

#include <cv_bridge/cv_bridge.h>
#include <mrpt/math/CQuaternion.h>
#include <sensor_msgs/image_encodings.h>
#include <sensor_msgs/point_cloud2_iterator.h>

#include <Eigen/Geometry>

#include <mutex>

#include "map/map_points_text.h"

namespace dynslam {

namespace {
std_msgs::Header header(double stamp, const std::string& frame_id) {
  std_msgs::Header h;
  h.stamp.fromSec(stamp);
  h.frame_id = frame_id;
  return h;
}

mrpt::math::CQuaternionDouble quaternion(const mrpt::poses::CPose3D& p) {
  mrpt::math::CQuaternionDouble q;
  p.getAsQuaternion(q);
  return q;
}
}  // namespace

geometry_msgs::PoseStamped poseMessage(const mrpt::poses::CPose3D& pose_wc, double stamp,
                                       const std::string& frame_id) {
  geometry_msgs::PoseStamped m;
  m.header = header(stamp, frame_id);
  m.pose.position.x = pose_wc.x();
  m.pose.position.y = pose_wc.y();
  m.pose.position.z = pose_wc.z();
  const auto q = quaternion(pose_wc);
  m.pose.orientation.x = q.x();
  m.pose.orientation.y = q.y();
  m.pose.orientation.z = q.z();
  m.pose.orientation.w = q.r();
  return m;
}

geometry_msgs::TransformStamped transformMessage(const mrpt::poses::CPose3D& pose_wc, double stamp,
                                                 const std::string& map_frame,
                                                 const std::string& camera_frame) {
  const geometry_msgs::PoseStamped p = poseMessage(pose_wc, stamp, map_frame);
  geometry_msgs::TransformStamped t;
  t.header = p.header;
  t.child_frame_id = camera_frame;
  t.transform.translation.x = p.pose.position.x;
  t.transform.translation.y = p.pose.position.y;
  t.transform.translation.z = p.pose.position.z;
  t.transform.rotation = p.pose.orientation;
  return t;
}

nav_msgs::OccupancyGrid gridMessage(const NavigationGrid& g, double stamp,
                                    const std::string& frame_id) {
  nav_msgs::OccupancyGrid m;
  m.header = header(stamp, frame_id);
  m.info.map_load_time = m.header.stamp;
  m.info.resolution = static_cast<float>(g.grid.resolution);
  m.info.width = static_cast<uint32_t>(g.grid.width);
  m.info.height = static_cast<uint32_t>(g.grid.height);
  // p_level = R p_map: the grid's corner in the map frame is R^T of its level
  // coordinates, and its axes are the level axes, R^T's columns.
  const Eigen::Matrix3d level_to_map = g.level.R.transpose();
  const Eigen::Vector3d corner =
      level_to_map * Eigen::Vector3d(g.grid.origin_x, g.grid.origin_y, g.level.floor_height);
  const Eigen::Quaterniond q(level_to_map);
  m.info.origin.position.x = corner.x();
  m.info.origin.position.y = corner.y();
  m.info.origin.position.z = corner.z();
  m.info.origin.orientation.x = q.x();
  m.info.origin.orientation.y = q.y();
  m.info.origin.orientation.z = q.z();
  m.info.origin.orientation.w = q.w();
  m.data.assign(g.grid.cells.begin(), g.grid.cells.end());
  return m;
}

sensor_msgs::PointCloud2 mapPointCloud(Map& map, double stamp, const std::string& frame_id) {
  sensor_msgs::PointCloud2 cloud;
  cloud.header = header(stamp, frame_id);
  sensor_msgs::PointCloud2Modifier mod(cloud);
  mod.setPointCloud2FieldsByString(2, "xyz", "rgb");
  std::lock_guard<std::mutex> lock(map.mutex());
  const std::vector<MapPoint*> points = map.mapPoints();
  mod.resize(points.size());
  sensor_msgs::PointCloud2Iterator<float> x(cloud, "x"), y(cloud, "y"), z(cloud, "z");
  sensor_msgs::PointCloud2Iterator<uint8_t> r(cloud, "r"), g(cloud, "g"), b(cloud, "b");
  for (const MapPoint* mp : points) {
    const cv::Vec3b bgr = mapPointBgr(*mp);
    *x = static_cast<float>(mp->pos.x());
    *y = static_cast<float>(mp->pos.y());
    *z = static_cast<float>(mp->pos.z());
    *r = bgr[2];
    *g = bgr[1];
    *b = bgr[0];
    ++x, ++y, ++z, ++r, ++g, ++b;
  }
  return cloud;
}

sensor_msgs::Image maskMessage(const cv::Mat& mask, double stamp, const std::string& frame_id) {
  sensor_msgs::Image m;
  cv_bridge::CvImage(header(stamp, frame_id), sensor_msgs::image_encodings::MONO8, mask)
      .toImageMsg(m);
  return m;
}

}  // namespace dynslam
