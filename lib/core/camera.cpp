#include "core/camera.h"

#include <mrpt/containers/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <regex>

#include "core/atomic_file.h"
#include "core/config_reader.h"
#include "core/data_paths.h"
#include "core/errors.h"
#include "core/yaml_writer.h"

namespace dynslam {

bool PinholeCamera::hasDistortion() const {
  for (double d : dist)
    if (d != 0.0) return true;
  return false;
}

mrpt::img::TCamera PinholeCamera::toMrpt() const {
  mrpt::img::TCamera c;
  c.ncols = static_cast<uint32_t>(width);
  c.nrows = static_cast<uint32_t>(height);
  c.setIntrinsicParamsFromValues(fx, fy, cx, cy);
  c.distortion =
      hasDistortion() ? mrpt::img::DistortionModel::plumb_bob : mrpt::img::DistortionModel::none;
  for (int i = 0; i < 5; ++i) c.dist[i] = dist[i];
  c.cameraName = name;
  return c;
}

PinholeCamera PinholeCamera::fromMrpt(const mrpt::img::TCamera& c) {
  PinholeCamera cam;
  cam.name = c.cameraName;
  cam.width = static_cast<int>(c.ncols);
  cam.height = static_cast<int>(c.nrows);
  cam.fx = c.fx();
  cam.fy = c.fy();
  cam.cx = c.cx();
  cam.cy = c.cy();
  for (int i = 0; i < 5; ++i) cam.dist[i] = c.dist[i];
  return cam;
}

bool PinholeCamera::sameGeometry(const PinholeCamera& o) const {
  auto same = [](double a, double b) {
    return std::abs(a - b) <= 1e-9 * std::max({1.0, std::abs(a), std::abs(b)});
  };
  if (width != o.width || height != o.height) return false;
  if (!same(fx, o.fx) || !same(fy, o.fy) || !same(cx, o.cx) || !same(cy, o.cy)) return false;
  for (int i = 0; i < 5; ++i)
    if (!same(dist[i], o.dist[i])) return false;
  return true;
}

void PinholeCamera::validate(const std::string& source) const {
  if (width <= 0 || height <= 0) throw InputError(source, "image width/height must be positive");
  // Bounds of any real camera: a focal length of 1e-300 or 1e300 px made
  // NaN map points and crashed the export (found by fuzzing).
  constexpr int kMaxSide = 16384;
  if (width > kMaxSide || height > kMaxSide)
    throw InputError(source, "image width/height must be at most " + std::to_string(kMaxSide));
  if (!(fx >= 1 && fx <= 1e6) || !(fy >= 1 && fy <= 1e6))
    throw InputError(source, "focal lengths fx, fy must be in 1..1e6 px");
  if (!(cx > 0 && cx < width) || !(cy > 0 && cy < height))
    throw InputError(source, "principal point (cx, cy) must lie inside the image");
  if (!(depth_scale > 0) || !(depth_scale <= 1e6))
    throw InputError(source, "depth_scale must be in (0, 1e6] (raw units per metre)");
  for (double d : dist)
    if (!(std::abs(d) <= 1e3))
      throw InputError(source, "distortion coefficients must be in -1e3..1e3");
}

PinholeCamera loadCameraYaml(const std::string& path) {
  requireRegularFile(path, "camera config");
  const mrpt::containers::yaml y = loadYamlFile(path);
  if (!y.isMap() || !y.has("camera")) throw InputError(path, "missing 'camera:' section");
  if (!y["camera"].isMap()) throw InputError(path, "'camera:' must be a map of key: value");
  ConfigSection c(y["camera"], path, "camera");
  for (const char* key : {"width", "height", "fx", "fy", "cx", "cy", "depth_scale"})
    if (!c.has(key)) throw InputError(path, std::string("missing camera.") + key);
  PinholeCamera cam;
  cam.name = std::filesystem::path(path).stem().string();
  c.read("name", cam.name)
      .read("width", cam.width)
      .read("height", cam.height)
      .read("fx", cam.fx)
      .read("fy", cam.fy)
      .read("cx", cam.cx)
      .read("cy", cam.cy)
      .read("k1", cam.dist[0])
      .read("k2", cam.dist[1])
      .read("p1", cam.dist[2])
      .read("p2", cam.dist[3])
      .read("k3", cam.dist[4])
      .read("depth_scale", cam.depth_scale);
  c.rejectUnknownKeys();  // a typo ("k4", "fx_") must not fall back to 0
  cam.validate(path);
  return cam;
}

std::string cameraConfigForSequence(const std::string& sequence_path) {
  // A sequence that carries its calibration (rendered ones: dynslam synth).
  const std::filesystem::path own = std::filesystem::path(sequence_path) / "camera.yaml";
  if (std::filesystem::is_directory(sequence_path) && std::filesystem::is_regular_file(own))
    return own.string();
  static const std::regex re("(freiburg|fr)([123])", std::regex::icase);
  std::smatch m;
  const std::string name = std::filesystem::path(sequence_path).lexically_normal().string();
  if (!std::regex_search(name, m, re)) {
    throw InputError(sequence_path,
                     "cannot tell the camera from the name (no freiburg1/2/3); "
                     "give a camera YAML (see configs/tum_fr1.yaml): run and export --camera "
                     "CAMERA.yaml, convert -c CAMERA.yaml");
  }
  return configDir() + "/tum_fr" + m[2].str() + ".yaml";
}

void writeCameraYaml(const std::string& path, const PinholeCamera& c, const std::string& comment) {
  YamlWriter y;
  y.comment(comment).beginSection("camera");
  y.value("name", c.name).value("width", c.width).value("height", c.height);
  y.value("fx", c.fx).value("fy", c.fy).value("cx", c.cx).value("cy", c.cy);
  y.value("k1", c.dist[0]).value("k2", c.dist[1]).value("p1", c.dist[2]);
  y.value("p2", c.dist[3]).value("k3", c.dist[4]).value("depth_scale", c.depth_scale);
  y.endSection();
  writeFileAtomically(path, [&](std::ostream& os) { os << y.str(); });
}

}  // namespace dynslam
