# All third-party dependencies, found once. Every one is a Debian 12 package
# installed by scripts/install-deps.sh.

# MRPT 2.5: each module is its own CMake package exporting mrpt::<module>.
foreach(m core containers math poses obs serialization io img system opengl graphs graphslam)
  find_package(mrpt-${m} REQUIRED)
endforeach()

# rgbd is opencv_contrib's module (libopencv-contrib-dev): rgbd::registerDepth
# re-projects a depth camera's range image into the RGB camera (rawlog/).
find_package(OpenCV 4 REQUIRED COMPONENTS core imgproc imgcodecs features2d video calib3d dnn rgbd)
find_package(Eigen3 3.3 REQUIRED NO_MODULE)
find_package(Ceres 2 REQUIRED)
find_package(GTest REQUIRED)

# PCL and assimp are only needed by the map exporter; found lazily by
# lib/mapexport so that the rest of the tree builds fast.
find_package(Threads REQUIRED)
find_package(PkgConfig REQUIRED)
# libyaml (libyaml-dev): its event parser walks a YAML file's structure
# before MRPT's recursive reader takes it (lib/core/yaml_structure.h).
pkg_check_modules(LIBYAML REQUIRED IMPORTED_TARGET yaml-0.1)

add_compile_definitions(DYNSLAM_VERSION="${PROJECT_VERSION}")

# TCLAP (command-line parsing), shipped inside MRPT's headers.
find_path(TCLAP_INCLUDE_DIR mrpt/3rdparty/tclap/CmdLine.h
  PATHS /usr/include/mrpt/tclap/include /usr/local/include/mrpt/tclap/include REQUIRED)
add_library(dynslam_tclap INTERFACE)
target_include_directories(dynslam_tclap INTERFACE "${TCLAP_INCLUDE_DIR}")
