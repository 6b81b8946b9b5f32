#pragma once
// What the node publishes, as ROS messages built from SLAM's outputs: kept
// apart from the node's wiring so the unit tests can check each message
// against the values it was made from, without a ROS master.
#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/TransformStamped.h>
#include <mrpt/poses/CPose3D.h>
#include <nav_msgs/OccupancyGrid.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>

#include <opencv2/core.hpp>

#include <string>

#include "map/map.h"
#include "occupancy/navigation_grid.h"

namespace dynslam {

/// The camera pose (camera-to-world, as trajectory.txt) in `frame_id`.
geometry_msgs::PoseStamped poseMessage(const mrpt::poses::CPose3D& pose_wc, double stamp,
                                       const std::string& frame_id);

/// The same pose as the TF map_frame -> camera_frame.
geometry_msgs::TransformStamped transformMessage(const mrpt::poses::CPose3D& pose_wc, double stamp,
                                                 const std::string& map_frame,
                                                 const std::string& camera_frame);

/// Every map point (x y z float32 and packed rgb, as map_points.txt), read
/// under the map's mutex (the local mapper changes it meanwhile).
sensor_msgs::PointCloud2 mapPointCloud(Map& map, double stamp, const std::string& frame_id);

/// The navigation grid in `frame_id` (the map frame): its cells as they are
/// (-1 unknown, 0 free, 100 occupied; row 0 = lowest level y), its origin the
/// corner of cell (0, 0) on the floor plane, its orientation the level
/// frame's (level_frame.h) in the map frame.
nav_msgs::OccupancyGrid gridMessage(const NavigationGrid& grid, double stamp,
                                    const std::string& frame_id);

/// The dynamic mask (CV_8U, 255 = dynamic) as a mono8 image.
sensor_msgs::Image maskMessage(const cv::Mat& mask, double stamp, const std::string& frame_id);

}  // namespace dynslam
