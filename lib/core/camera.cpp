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
#include "core/value_range.h"
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

namespace {

/// The largest image side of any camera (and of the image decoder).
constexpr int kMaxImageSide = 16384;

/// The valid range of each real-valued camera key, quoted in the keys'
/// comments in configs/tum_fr*.yaml. Bounds of any real camera: a focal
/// length of 1e-300 or 1e300 px made NaN map points and crashed the export
/// (found by fuzzing). Depth sensors store millimetres (1000 units per metre)
/// or fifths of one (TUM: 5000); 100 still takes centimetres, and the 16-bit
/// maximum (65535) then lies 655 m away: a depth_scale that puts it
/// kilometres away (10: 6.5 km) made a trajectory that eval and export
/// refuse, and one above 1e5 leaves the sensor under 0.66 m of range.
const KeyRanges& cameraKeyRanges() {
  static const KeyRanges ranges = {
      {"fx", closedRange(1, 1e6)},         {"fy", closedRange(1, 1e6)},
      {"cx", openRange(0, kMaxImageSide)}, {"cy", openRange(0, kMaxImageSide)},
      {"k1", closedRange(-1e3, 1e3)},      {"k2", closedRange(-1e3, 1e3)},
      {"p1", closedRange(-1e3, 1e3)},      {"p2", closedRange(-1e3, 1e3)},
      {"k3", closedRange(-1e3, 1e3)},      {"depth_scale", closedRange(100, 1e5)},
  };
  return ranges;
}

}  // namespace

void PinholeCamera::validate(const std::string& source) const {
  const auto fail = [&](const std::string& key, const std::string& what) {
    failAtKey(source, "camera." + key, "camera." + key + ": " + what);
  };
  if (width <= 0 || width > kMaxImageSide)
    fail("width", "must be in 1.." + std::to_string(kMaxImageSide) + " px");
  if (height <= 0 || height > kMaxImageSide)
    fail("height", "must be in 1.." + std::to_string(kMaxImageSide) + " px");
  const PinholeCamera& c = *this;
  requireOptionRanges(
      [&](auto&& f) {
        f("fx", c.fx);
        f("fy", c.fy);
        f("cx", c.cx);
        f("cy", c.cy);
        f("k1", c.dist[0]);
        f("k2", c.dist[1]);
        f("p1", c.dist[2]);
        f("p2", c.dist[3]);
        f("k3", c.dist[4]);
        f("depth_scale", c.depth_scale);
      },
      cameraKeyRanges(), source, "camera.");
  if (!(cx < width)) fail("cx", "the principal point must lie inside the image (cx < width)");
  if (!(cy < height)) fail("cy", "the principal point must lie inside the image (cy < height)");
}

PinholeCamera loadCameraYaml(const std::string& path) {
  requireRegularFile(path, "camera config");
  const mrpt::containers::yaml y = loadYamlFile(path);
  if (!y.isMap() || !y.has("camera")) throw InputError(path, "missing 'camera:' section");
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
