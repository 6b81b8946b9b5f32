#pragma once
// Pinhole RGB-D camera model with Brown-Conrady distortion, loaded from the
// YAML files in configs/ (tum_fr1.yaml ...). One struct is shared by the data
// layer, the tracker and the exporters so that intrinsics live in one place.
#include <mrpt/img/TCamera.h>

#include <array>
#include <string>

namespace dynslam {

struct PinholeCamera {
  int width = 640;
  int height = 480;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  /// k1 k2 p1 p2 k3 (OpenCV order); all zero for rectified images.
  std::array<double, 5> dist{0, 0, 0, 0, 0};
  /// Raw depth units per metre (TUM: 5000).
  double depth_scale = 5000.0;
  /// Name of the config it came from (for reports).
  std::string name;

  bool hasDistortion() const;
  mrpt::img::TCamera toMrpt() const;
  /// Size, intrinsics, distortion and name of an MRPT camera; depth_scale is
  /// left at its default (MRPT keeps depth units elsewhere).
  static PinholeCamera fromMrpt(const mrpt::img::TCamera& c);
  /// Same size, intrinsics and distortion (to 1e-9 relative); names and
  /// depth_scale are not compared.
  bool sameGeometry(const PinholeCamera& other) const;
  /// Throws InputError(source) if a value is out of range.
  void validate(const std::string& source) const;
};

/// Reads a camera YAML file (see configs/tum_fr1.yaml for the keys).
/// Throws InputError naming the file on missing keys or bad values.
PinholeCamera loadCameraYaml(const std::string& path);

/// Writes `camera` as a camera YAML that loadCameraYaml reads back exactly
/// (configs/tum_fr1.yaml's keys), atomically; `comment` goes on top.
void writeCameraYaml(const std::string& path, const PinholeCamera& camera,
                     const std::string& comment);

/// The sequence folder's own camera.yaml when it has one (rendered sequences),
/// else configDir()/tum_fr{1,2,3}.yaml (core/data_paths.h) from a sequence path containing
/// "freiburg1/2/3" (or "fr1/2/3"); throws InputError naming the path if none.
std::string cameraConfigForSequence(const std::string& sequence_path);

}  // namespace dynslam
