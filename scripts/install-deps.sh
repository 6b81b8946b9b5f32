#!/usr/bin/env bash
# Installs every Debian 12 package dynslam needs to build, test and benchmark.
# Idempotent: packages already present are left alone; safe to run repeatedly.
set -euo pipefail

PACKAGES=(
  build-essential cmake pkg-config
  libmrpt-dev mrpt-apps            # poses, Lie algebra, rawlogs, graph-SLAM, opengl; rawlog-edit for checks
  libopencv-dev                    # images, ORB/FAST, LK flow, RANSAC, DNN (ONNX)
  libopencv-contrib-dev            # rgbd::registerDepth (depth camera -> RGB camera in rawlogs)
  libeigen3-dev                    # linear algebra, umeyama
  libpcl-dev                       # voxel grid, outlier removal, PLY I/O
  libassimp-dev                    # glTF 2.0 export
  liboctomap-dev octomap-tools     # OctoMap export (.bt); convert_octree/bt2vrml check the files
  libosmesa6-dev                   # off-screen rendering without X or GPU
  libceres-dev                     # bundle adjustment
  libyaml-dev                      # YAML structure check before MRPT's parser (lib/core/yaml_structure.h)
  libpng-dev libjpeg-dev           # PNG / JPEG frames decoded with their errors caught (rawlog/image_decoder.h)
  libgtest-dev                     # unit tests
  clang libclang-rt-14-dev         # libFuzzer + AddressSanitizer: the fuzzing smoke test (tests/faults/fuzz)
  parallel                         # GNU parallel: runs `dynslam bench --emit-jobs` files (README, bench test)
  python3 python3-opencv python3-numpy  # only for ../shared/tools/make_dynamic_sequence.py (test data)
  # ROS 1 (optional for the build, installed so CI builds and tests it; cmake/DynslamRos.cmake):
  librosbag-storage-dev pluginlib-dev    # rosbag::Bag / View (bags as input); pluginlib: its headers
  libcv-bridge-dev                       # ROS images <-> cv::Mat
  libsensor-msgs-dev libgeometry-msgs-dev libnav-msgs-dev libtf2-msgs-dev libstd-srvs-dev
  libroscpp-dev libmessage-filters-dev   # dynslam_node: topics, approximate-time sync
  libtf2-ros-dev                         # dynslam_node: map -> odom from the robot's TF (REP 105)
  ros-core python3-rosbag                # roscpp's master (roscore), rosbag play/record (node test)
  python3-std-srvs                       # `rosservice call /dynslam/save` (std_srvs/Empty)
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#PACKAGES[@]} packages already installed"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "install-deps: installing ${missing[*]}"
$SUDO apt-get update -q
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
