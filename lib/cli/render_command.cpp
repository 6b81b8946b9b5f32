// `dynslam render MAP.ply|MAP.glb -o OUT.png`: thin argument layer over
// render/ (off-screen OSMesa snapshots of an exported map).
#include <mrpt/3rdparty/tclap/CmdLine.h>
#include <mrpt/math/CQuaternion.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>

#include "cli/commands.h"
#include "core/errors.h"
#include "core/map_bounds.h"
#include "core/png_file.h"
#include "core/run_counts.h"
#include "core/trajectory.h"
#include "mapexport/map_data.h"
#include "mapexport/up_estimation.h"
#include "occupancy/octomap_file.h"
#include "render/map_renderer.h"
#include "render/view_spec.h"

namespace dynslam::cli {
namespace {

constexpr const char* kDescription =
    "Off-screen snapshot (PNG) of a map written by `dynslam export`: coloured points, the "
    "keyframe trajectory (red) and keyframe frustums (blue). Needs no display or GPU (Mesa "
    "OSMesa software rendering). Named views are framed on the map (median centre, 95 % "
    "radius, keyframes included); 'up' is the normal of the largest floor / desk plane "
    "(RANSAC; the plane must face the cameras and lie within 60 deg of the keyframes' mean "
    "image-up axis), else that axis, or given with --up. Keyframes come from a .glb map or from "
    "--trajectory.";

/// "a,b,c" -> three numbers; throws UsageError naming `what`.
std::array<double, 3> parseTriple(const std::string& text, const std::string& what) {
  std::string s = text;
  for (char& c : s)
    if (c == ',') c = ' ';
  std::istringstream in(s);
  std::array<double, 3> v{};
  std::string rest;
  if (!(in >> v[0] >> v[1] >> v[2]) || (in >> rest)) {
    throw UsageError(what + ": expected three comma-separated numbers, got '" + text + "'");
  }
  return v;
}

}  // namespace

int renderMain(int argc, char** argv) {
  TCLAP::CmdLine cmd(kDescription, ' ', DYNSLAM_VERSION);
  TCLAP::UnlabeledValueArg<std::string> map_arg(
      "map",
      "map file (.ply or .glb; .bt: an OctoMap's occupied cells, drawn as cubes coloured by "
      "height)",
      true, "", "MAP", cmd);
  TCLAP::ValueArg<std::string> out_arg("o", "output", "PNG file to write", true, "", "OUT.png",
                                       cmd);
  TCLAP::ValueArg<std::string> view_arg(
      "", "view",
      "top (looking down, image-up = mean viewing direction), front (from behind the cameras, "
      "25 deg above the horizon), orbit-N (front turned N degrees about up) or "
      "pose:x,y,z,qx,qy,qz,qw (camera-to-world; +z forward, +x right, +y down)",
      false, "top", "VIEW", cmd);
  TCLAP::ValueArg<int> width_arg("", "width", "image width in pixels", false, 1280, "W", cmd);
  TCLAP::ValueArg<int> height_arg("", "height", "image height in pixels", false, 960, "H", cmd);
  TCLAP::ValueArg<float> point_arg("", "point-size", "point size in pixels", false, 2.f, "S", cmd);
  TCLAP::ValueArg<double> fov_arg("", "fov", "vertical field of view in degrees", false, 50.0,
                                  "DEG", cmd);
  TCLAP::ValueArg<std::string> traj_arg(
      "", "trajectory",
      "keyframe poses (TUM format, e.g. RUN_DIR/keyframes.txt) to draw, replacing those of a "
      ".glb",
      false, "", "FILE", cmd);
  TCLAP::ValueArg<std::string> bg_arg("", "background", "background colour R,G,B (0-255)", false,
                                      "255,255,255", "R,G,B", cmd);
  TCLAP::ValueArg<std::string> up_arg(
      "", "up",
      "world up direction x,y,z (default: floor / desk plane normal, else the keyframes' "
      "image-up axis, else +z)",
      false, "", "X,Y,Z", cmd);
  TCLAP::SwitchArg no_frustums_arg("", "no-frustums", "do not draw keyframe frustums", cmd, false);
  TCLAP::SwitchArg no_traj_arg("", "no-trajectory", "do not draw the trajectory line", cmd, false);
  int exit_code = kOk;
  if (!parseArguments(cmd, argc, argv, exit_code)) return exit_code;

  RenderOptions o;
  o.width = width_arg.getValue();
  o.height = height_arg.getValue();
  o.point_size = point_arg.getValue();
  o.vertical_fov_deg = fov_arg.getValue();
  o.draw_frustums = !no_frustums_arg.getValue();
  o.draw_trajectory = !no_traj_arg.getValue();
  const auto bg = parseTriple(bg_arg.getValue(), "--background");
  for (int k = 0; k < 3; ++k) {
    if (bg[k] < 0 || bg[k] > 255) throw UsageError("--background: values 0..255");
    o.background[k] = static_cast<std::uint8_t>(bg[k]);
  }
  if (up_arg.isSet()) {
    o.up = parseTriple(up_arg.getValue(), "--up");
    const auto& u = *o.up;
    if (!(u[0] * u[0] + u[1] * u[1] + u[2] * u[2] > 1e-12) || !std::isfinite(u[0] + u[1] + u[2]))
      throw UsageError("--up: expected a non-zero, finite direction, got '" + up_arg.getValue() +
                       "'");
  }
  {
    std::string ext = std::filesystem::path(out_arg.getValue()).extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (ext != ".png")  // it wrote PNG data under any name (x.jpg)
      throw UsageError("-o/--output: the snapshot is a PNG, the name must end in .png, got '" +
                       out_arg.getValue() + "'");
  }
  ViewSpec view;
  try {  // bad values on the command line: usage errors, before any work
    view = ViewSpec::parse(view_arg.getValue());
    MapRenderer::checkOptions(o);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }

  const std::string& path = map_arg.getValue();
  if (!isOctoMapPath(path)) {
    try {
      mapFormatFromPath(path);
    } catch (const InputError&) {  // its advice leaves out the OctoMap that render also reads
      throw InputError(path, "unknown map format (use a .ply, .glb or .bt extension)");
    }
  }
  MapData map =
      isOctoMapPath(path) ? occupiedCellsAsMap(*readOctoMapFile(path), path) : readMapFile(path);
  if (traj_arg.isSet()) {
    // A run's keyframes.txt or trajectory.txt cut short or edited since the
    // run was drawn as if whole (issue 57).
    checkRunFileAgainstReport(traj_arg.getValue());
    map.keyframes = readTumTrajectory(traj_arg.getValue());
  }
  // Keyframes are framed with the points: one thousands of km away leaves
  // the map a dot (the points' own bound, core/map_bounds.h).
  const std::string& keyframe_source = traj_arg.isSet() ? traj_arg.getValue() : path;
  for (std::size_t i = 0; i < map.keyframes.size(); ++i) {
    const auto& p = map.keyframes[i].pose;
    if (!(std::max({std::abs(p.x()), std::abs(p.y()), std::abs(p.z())}) <= kMaxMapCoordinate))
      throw InputError(keyframe_source, "keyframe " + std::to_string(i + 1) + " lies beyond " +
                                            std::to_string(int(kMaxMapCoordinate / 1000)) +
                                            " km of the origin, where no map point may be");
  }

  std::string up_note = "given";
  if (!o.up) {
    const UpEstimate up = estimateMapUp(map);
    o.up = up.up;
    char buf[160];
    std::snprintf(buf, sizeof buf, "%s, %.1f deg from the keyframe estimate", up.source.c_str(),
                  up.prior_angle_deg);
    up_note = buf;
  }
  MapRenderer renderer(o);
  const mrpt::poses::CPose3D camera_pose = renderer.cameraPose(map, view);
  // Nothing in view would be a picture of the background alone.
  if (!renderer.showsAnyPoint(map, camera_pose)) {
    const std::string what = "no point of the map lies in the view '" + view_arg.getValue() + "'";
    if (view.kind == ViewSpec::Kind::kPose)
      throw UsageError("--view: " + what + " of " + path + " (it looks away or is too far)");
    throw InputError(path, what + " (the map is too large, or too small, to be framed)");
  }
  const cv::Mat image = renderer.renderFromPose(map, camera_pose);
  writePngAtomically(out_arg.getValue(), image);
  std::printf("%s: %dx%d, %zu points, %zu keyframes, view %s, up %.4f,%.4f,%.4f (%s)\n",
              out_arg.getValue().c_str(), image.cols, image.rows, map.points.size(),
              map.keyframes.size(), view_arg.getValue().c_str(), (*o.up)[0], (*o.up)[1], (*o.up)[2],
              up_note.c_str());
  // The same viewpoint for other maps of the same world frame (e.g. runs of
  // one sequence): pass this back as --view.
  mrpt::math::CQuaternionDouble q;
  camera_pose.getAsQuaternion(q);
  std::printf("camera --view pose:%.4f,%.4f,%.4f,%.6f,%.6f,%.6f,%.6f\n", camera_pose.x(),
              camera_pose.y(), camera_pose.z(), q.x(), q.y(), q.z(), q.w());
  return kOk;
}

}  // namespace dynslam::cli
