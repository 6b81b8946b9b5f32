#include "tum_bag_writer.h"

#include <cv_bridge/cv_bridge.h>
#include <rosbag/bag.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/CompressedImage.h>
#include <tf2_msgs/TFMessage.h>
#include <opencv2/imgproc.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <stdexcept>

#include "core/camera.h"
#include "rawlog/tum_folder_source.h"
#include "testing/test_support.h"

namespace dynslam::test {

namespace {

/// Groundtruth written this long before the first and after the last frame.
constexpr double kGroundtruthMargin = 0.5;

std::vector<uint8_t> fileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// One /tf message world -> `child` at time t; `txyz_qxyzw` as a TUM
/// groundtruth line writes it (tx ty tz qx qy qz qw).
/// parent -> child at time t; `txyz_qxyzw` as a TUM groundtruth line writes
/// it (tx ty tz qx qy qz qw).
geometry_msgs::TransformStamped transformStamped(double t, const std::string& parent,
                                                 const std::string& child,
                                                 const double* txyz_qxyzw) {
  const double* v = txyz_qxyzw;
  geometry_msgs::TransformStamped ts;
  ts.header = header(t, parent);
  ts.child_frame_id = child;
  ts.transform.translation.x = v[0];
  ts.transform.translation.y = v[1];
  ts.transform.translation.z = v[2];
  ts.transform.rotation.x = v[3];
  ts.transform.rotation.y = v[4];
  ts.transform.rotation.z = v[5];
  ts.transform.rotation.w = v[6];
  return ts;
}

void writeWorldTf(rosbag::Bag& bag, double t, const char* child, const double* txyz_qxyzw) {
  tf2_msgs::TFMessage tf;
  tf.transforms.push_back(transformStamped(t, "/world", child, txyz_qxyzw));
  bag.write("/tf", ros::Time().fromSec(t), tf);
}

/// Frame i's RGB header.seq.
std::size_t rgbSeq(const TumBagSpec& spec, std::size_t i) {
  return spec.rgb_seq_gap_every > 0 ? i + i / spec.rgb_seq_gap_every : i;
}

}  // namespace

std_msgs::Header header(double t, const std::string& frame, std::size_t seq) {
  std_msgs::Header h;
  h.seq = static_cast<uint32_t>(seq);
  h.stamp.fromSec(t);
  h.frame_id = frame;
  return h;
}

sensor_msgs::CameraInfo cameraInfoMessage(const PinholeCamera& cam, double t, std::size_t seq) {
  sensor_msgs::CameraInfo info;
  info.header = header(t, kTumRgbFrame, seq);
  info.width = static_cast<uint32_t>(cam.width);
  info.height = static_cast<uint32_t>(cam.height);
  info.distortion_model = "plumb_bob";
  info.D.assign(cam.dist.begin(), cam.dist.end());
  info.K = {cam.fx, 0, cam.cx, 0, cam.fy, cam.cy, 0, 0, 1};
  info.R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  info.P = {cam.fx, 0, cam.cx, 0, 0, cam.fy, cam.cy, 0, 0, 0, 1, 0};
  return info;
}

std::size_t skippedRgbSeqs(const TumBagSpec& spec) {
  return spec.frames == 0 ? 0 : rgbSeq(spec, spec.frames - 1) - (spec.frames - 1);
}

std::vector<double> writeTumBag(const std::string& path, const TumBagSpec& spec) {
  const TumFolderSource src(rpyDir(), sourceDir() + "/configs/tum_fr1.yaml");
  const PinholeCamera& cam = src.camera();
  const std::size_t n = std::min(spec.frames, src.size());
  rosbag::Bag bag(path, rosbag::bagmode::Write);
  if (spec.lz4) bag.setCompression(rosbag::compression::LZ4);
  std::vector<double> stamps;
  if (!spec.static_tf.empty() && n > 0) {
    tf2_msgs::TFMessage tf;
    const double t0 = src.timestamp(0) - kGroundtruthMargin;
    for (const StaticTf& s : spec.static_tf)
      tf.transforms.push_back(transformStamped(t0, s.parent, s.child, s.xyz_qxyzw));
    // A connection header of its own (rosbag then stores it as given), as
    // `rosbag record` writes a latched topic.
    auto latched = boost::make_shared<ros::M_string>();
    (*latched)["type"] = ros::message_traits::datatype(tf);
    (*latched)["md5sum"] = ros::message_traits::md5sum(tf);
    (*latched)["message_definition"] = ros::message_traits::definition(tf);
    (*latched)["callerid"] = "/static_tf";
    (*latched)["latching"] = "1";
    bag.write("/tf_static", ros::Time().fromSec(t0), tf, latched);
  }
  for (std::size_t i = 0; i < n; ++i) {
    const double t = src.timestamp(i);
    const ros::Time rt = ros::Time().fromSec(t);
    stamps.push_back(t);

    if (spec.camera_info) bag.write("/camera/rgb/camera_info", rt, cameraInfoMessage(cam, t, i));
    if (!spec.images) continue;

    const RGBDFrame f = src.load(i);
    if (spec.compressed_rgb) {
      sensor_msgs::CompressedImage c;
      c.header = header(t, kTumRgbFrame, rgbSeq(spec, i));
      c.format = "jpeg";
      c.data = fileBytes(src.rgbPath(i));
      bag.write(spec.rgb_topic, rt, c);
    } else {
      cv::Mat rgb;
      cv::cvtColor(f.rgb, rgb, cv::COLOR_BGR2RGB);
      sensor_msgs::ImagePtr m =
          cv_bridge::CvImage(header(t, kTumRgbFrame, rgbSeq(spec, i)), "rgb8", rgb).toImageMsg();
      m->encoding = spec.rgb_encoding;
      bag.write(spec.rgb_topic, rt, *m);
      for (const std::string& extra : spec.extra_image_topics) bag.write(extra, rt, *m);
    }

    cv::Mat depth16 = f.depth;
    if (spec.depth_width > 0)
      cv::resize(f.depth, depth16,
                 cv::Size(spec.depth_width, spec.depth_width * f.depth.rows / f.depth.cols), 0, 0,
                 cv::INTER_NEAREST);
    cv::Mat depth;
    std::string encoding = spec.depth_encoding;
    if (spec.depth_encoding == "32FC1") {
      // TUM's bags: metres, NaN where the sensor measured nothing.
      depth16.convertTo(depth, CV_32FC1, 1.0 / kTumDepthUnitsPerMetre);
      depth.setTo(std::numeric_limits<float>::quiet_NaN(), depth16 == 0);
    } else {
      depth16.convertTo(depth, CV_16UC1, kRosDepthUnitsPerMetre / kTumDepthUnitsPerMetre);
    }
    const double td = f.depth_timestamp;
    sensor_msgs::ImagePtr d =
        cv_bridge::CvImage(header(td, kTumDepthFrame, i),
                           spec.depth_encoding == "32FC1" ? "32FC1" : "16UC1", depth)
            .toImageMsg();
    d->encoding = encoding;
    bag.write(spec.depth_topic, ros::Time().fromSec(td), *d);
  }

  if (spec.groundtruth) {
    // The file's numbers as written (no pose class in between): the test
    // compares what comes back out of the bag with this same file.
    std::ifstream gt(rpyDir() + "/groundtruth.txt");
    std::string line;
    while (std::getline(gt, line)) {
      double v[8];
      if (line.empty() || line[0] == '#' ||
          std::sscanf(line.c_str(), "%lf %lf %lf %lf %lf %lf %lf %lf", &v[0], &v[1], &v[2], &v[3],
                      &v[4], &v[5], &v[6], &v[7]) != 8)
        continue;
      if (v[0] < stamps.front() - kGroundtruthMargin || v[0] > stamps.back() + kGroundtruthMargin)
        continue;
      writeWorldTf(bag, v[0], "/kinect", &v[1]);
    }
  }
  if (spec.end_padding_s > 0 && !stamps.empty()) {
    const double identity[7] = {0, 0, 0, 0, 0, 0, 1};
    writeWorldTf(bag, stamps.back() + spec.end_padding_s, "/padding", identity);
  }
  bag.close();
  return stamps;
}

}  // namespace dynslam::test
