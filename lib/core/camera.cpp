#include "core/camera.h"

#include <mrpt/containers/yaml.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <regex>

#include "core/atomic_file.h"
#include "core/errors.h"

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
  c.distortion = hasDistortion() ? mrpt::img::DistortionModel::plumb_bob
                                 : mrpt::img::DistortionModel::none;
  for (int i = 0; i < 5; ++i) c.dist[i] = dist[i];
  c.cameraName = name;
  return c;
}

void PinholeCamera::validate(const std::string& source) const {
  if (width <= 0 || height <= 0)
    throw InputError(source, "image width/height must be positive");
  if (!(fx > 0) || !(fy > 0) || !std::isfinite(fx) || !std::isfinite(fy))
    throw InputError(source, "focal lengths fx, fy must be positive");
  if (!(cx > 0 && cx < width) || !(cy > 0 && cy < height))
    throw InputError(source, "principal point (cx, cy) must lie inside the image");
  if (!(depth_scale > 0) || !std::isfinite(depth_scale))
    throw InputError(source, "depth_scale must be positive");
  for (double d : dist)
    if (!std::isfinite(d)) throw InputError(source, "distortion must be finite");
}

PinholeCamera loadCameraYaml(const std::string& path) {
  if (!fileExists(path)) throw InputError(path, "camera config not found");
  mrpt::containers::yaml y;
  try {
    y = mrpt::containers::yaml::FromFile(path);
  } catch (const std::exception& e) {
    throw InputError(path, std::string("not valid YAML: ") + e.what());
  }
  if (!y.isMap() || !y.has("camera"))
    throw InputError(path, "missing 'camera:' section");
  const auto& c = y["camera"];
  if (!c.isMap()) throw InputError(path, "'camera:' must be a map of key: value");
  auto num = [&](const char* key) -> double {
    if (!c.has(key)) throw InputError(path, std::string("missing camera.") + key);
    try {
      return c[key].as<double>();
    } catch (const std::exception&) {
      throw InputError(path, std::string("camera.") + key + " is not a number");
    }
  };
  PinholeCamera cam;
  cam.name = c.has("name") ? c["name"].as<std::string>()
                           : std::filesystem::path(path).stem().string();
  cam.width = static_cast<int>(num("width"));
  cam.height = static_cast<int>(num("height"));
  cam.fx = num("fx");
  cam.fy = num("fy");
  cam.cx = num("cx");
  cam.cy = num("cy");
  const char* dk[5] = {"k1", "k2", "p1", "p2", "k3"};
  for (int i = 0; i < 5; ++i) cam.dist[i] = c.has(dk[i]) ? num(dk[i]) : 0.0;
  cam.depth_scale = num("depth_scale");
  cam.validate(path);
  return cam;
}

std::string configDir() {
  if (const char* env = std::getenv("DYNSLAM_CONFIG_DIR"); env && *env) return env;
  return std::string(DYNSLAM_SOURCE_DIR) + "/configs";
}

std::string cameraConfigForSequence(const std::string& sequence_path) {
  static const std::regex re("(freiburg|fr)([123])", std::regex::icase);
  std::smatch m;
  const std::string name =
      std::filesystem::path(sequence_path).lexically_normal().string();
  if (!std::regex_search(name, m, re)) {
    throw InputError(sequence_path,
                     "cannot tell the camera from the name (no freiburg1/2/3); "
                     "pass --config CAMERA.yaml");
  }
  return configDir() + "/tum_fr" + m[2].str() + ".yaml";
}

}  // namespace dynslam
