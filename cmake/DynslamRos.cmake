# ROS 1 (Debian 12's Noetic-era packages, installed by scripts/install-deps.sh):
# optional. When found, dynslam reads ROS bags (rawlog/bag_*.cpp) and the
# ROS node (ros/, apps/dynslam_node.cpp) is built; without them the core
# builds as before and `dynslam run X.bag` says how to get bag support.
#
# Debian's catkin-generated CMake configs for rosbag_storage pull in ROS 2's
# ament machinery (pluginlib), and its pkg-config file names a pluginlib.pc
# that does not exist, so the pieces are found directly. Sets DYNSLAM_ROS_FOUND
# and the INTERFACE targets dynslam_ros_bag (rosbag + cv_bridge) and
# dynslam_ros_node (roscpp + message_filters + tf2_ros on top).
option(DYNSLAM_WITH_ROS "Build ROS bag input and the ROS node when ROS 1 is installed" ON)
set(DYNSLAM_ROS_FOUND OFF)
if(DYNSLAM_WITH_ROS)
  find_path(DYNSLAM_ROSBAG_INCLUDE_DIR rosbag/bag.h)
  find_path(DYNSLAM_PLUGINLIB_INCLUDE_DIR pluginlib/class_loader.hpp PATH_SUFFIXES pluginlib)
  find_path(DYNSLAM_CLASS_LOADER_INCLUDE_DIR class_loader/class_loader.hpp PATH_SUFFIXES class_loader)
  find_path(DYNSLAM_RCPPUTILS_INCLUDE_DIR rcpputils/shared_library.hpp PATH_SUFFIXES rcpputils)
  find_path(DYNSLAM_RCUTILS_INCLUDE_DIR rcutils/types.h PATH_SUFFIXES rcutils)
  find_path(DYNSLAM_AMENT_INDEX_INCLUDE_DIR ament_index_cpp/get_package_prefix.hpp
    PATH_SUFFIXES ament_index_cpp)
  find_path(DYNSLAM_SENSOR_MSGS_INCLUDE_DIR sensor_msgs/Image.h)
  find_path(DYNSLAM_TF2_MSGS_INCLUDE_DIR tf2_msgs/TFMessage.h)
  find_path(DYNSLAM_TF2_ROS_INCLUDE_DIR tf2_ros/buffer.h)
  find_path(DYNSLAM_NAV_MSGS_INCLUDE_DIR nav_msgs/Path.h)
  find_path(DYNSLAM_CV_BRIDGE_INCLUDE_DIR cv_bridge/cv_bridge.h)
  set(_bag_libs rosbag_storage roslz4 roscpp_serialization rostime cpp_common console_bridge
    cv_bridge)
  set(_node_libs roscpp message_filters xmlrpcpp rosconsole tf2_ros tf2)
  set(_missing "")
  foreach(v ROSBAG PLUGINLIB CLASS_LOADER RCPPUTILS RCUTILS AMENT_INDEX SENSOR_MSGS TF2_MSGS
      TF2_ROS NAV_MSGS CV_BRIDGE)
    if(NOT DYNSLAM_${v}_INCLUDE_DIR)
      list(APPEND _missing "${v} headers")
    endif()
  endforeach()
  foreach(l ${_bag_libs} ${_node_libs})
    find_library(DYNSLAM_ROS_LIB_${l} ${l})
    if(NOT DYNSLAM_ROS_LIB_${l})
      list(APPEND _missing "lib${l}")
    endif()
  endforeach()
  find_package(Boost QUIET COMPONENTS filesystem thread system)
  if(NOT Boost_FOUND)
    list(APPEND _missing "boost filesystem/thread/system")
  endif()
  if(_missing)
    message(STATUS "ROS 1 not found (missing: ${_missing}): no bag input, no dynslam_node "
      "(scripts/install-deps.sh installs them)")
  else()
    set(DYNSLAM_ROS_FOUND ON)
    add_library(dynslam_ros_bag INTERFACE)
    # SYSTEM: ROS headers are not ours to warn about.
    target_include_directories(dynslam_ros_bag SYSTEM INTERFACE
      ${DYNSLAM_ROSBAG_INCLUDE_DIR} ${DYNSLAM_PLUGINLIB_INCLUDE_DIR}
      ${DYNSLAM_CLASS_LOADER_INCLUDE_DIR} ${DYNSLAM_RCPPUTILS_INCLUDE_DIR}
      ${DYNSLAM_RCUTILS_INCLUDE_DIR} ${DYNSLAM_AMENT_INDEX_INCLUDE_DIR})
    foreach(l ${_bag_libs})
      target_link_libraries(dynslam_ros_bag INTERFACE ${DYNSLAM_ROS_LIB_${l}})
    endforeach()
    target_link_libraries(dynslam_ros_bag INTERFACE Boost::filesystem Boost::system)
    add_library(dynslam_ros_node INTERFACE)
    target_link_libraries(dynslam_ros_node INTERFACE dynslam_ros_bag Boost::thread)
    foreach(l ${_node_libs})
      target_link_libraries(dynslam_ros_node INTERFACE ${DYNSLAM_ROS_LIB_${l}})
    endforeach()
    message(STATUS "ROS 1 found: bag input and dynslam_node are built")
  endif()
endif()
