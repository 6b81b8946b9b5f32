#pragma once
// The ROS bag topic options shared by `dynslam run` and `dynslam convert`, so
// both name and document them alike (rawlog/bag_source.h chooses the topics
// that are not given).
#include <mrpt/3rdparty/tclap/CmdLine.h>

#include <string>

namespace dynslam {
struct BagTopics;  // rawlog/sequence_source.h
}

namespace dynslam::cli {

class BagTopicArgs {
 public:
  explicit BagTopicArgs(TCLAP::CmdLine& cmd)
      : rgb_("", "rgb-topic",
             "ROS bag only: the RGB topic (sensor_msgs/Image rgb8/bgr8 or CompressedImage; "
             "default: /camera/rgb/image_color if present, else the only image topic besides "
             "the depth one)",
             false, "", "TOPIC", cmd),
        depth_("", "depth-topic",
               "ROS bag only: the depth topic (sensor_msgs/Image, 32FC1 metres or 16UC1 "
               "millimetres; default: /camera/depth/image if present, else the only Image topic "
               "named *depth*)",
               false, "", "TOPIC", cmd),
        info_("", "camera-info-topic",
              "ROS bag only: the RGB camera's sensor_msgs/CameraInfo (default: "
              "/camera/rgb/camera_info, else RGB_TOPIC's sibling camera_info, else the only "
              "one); --camera replaces it",
              false, "", "TOPIC", cmd) {}

  BagTopics value();

 private:
  TCLAP::ValueArg<std::string> rgb_, depth_, info_;
};

}  // namespace dynslam::cli
