#include "render/map_renderer.h"

#include <mrpt/img/CImage.h>
#include <mrpt/opengl/CFBORender.h>
#include <mrpt/opengl/CFrustum.h>
#include <mrpt/opengl/COctoMapVoxels.h>
#include <mrpt/opengl/COpenGLScene.h>
#include <mrpt/opengl/CPointCloudColoured.h>
#include <mrpt/opengl/CSetOfLines.h>

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "render/offscreen_context.h"

namespace dynslam {
namespace {

/// Rotation from MRPT's "+x forward" object frame (CFrustum) to the optical
/// frame (+z forward, +x right, +y down): columns are the object axes
/// (forward, left, up) in optical coordinates.
mrpt::poses::CPose3D xForwardToOptical() {
  mrpt::math::CMatrixDouble33 R;
  R(0, 0) = 0;
  R(0, 1) = -1;
  R(0, 2) = 0;
  R(1, 0) = 0;
  R(1, 1) = 0;
  R(1, 2) = -1;
  R(2, 0) = 1;
  R(2, 1) = 0;
  R(2, 2) = 0;
  return mrpt::poses::CPose3D(R, mrpt::math::CVectorFixedDouble<3>::Zero());
}

/// Voxel maps (map.voxel_size > 0) as shaded cubes coloured by their height
/// along `up` (turbo colour map over the 2nd..98th percentile), as octovis
/// draws OctoMaps: cells carry no colour of their own.
mrpt::opengl::COctoMapVoxels::Ptr voxelCubes(const MapData& map, const std::array<double, 3>& up) {
  using mrpt::opengl::COctoMapVoxels;
  const std::size_t n = map.points.size();
  std::vector<double> h(n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto& p = map.points[i];
    h[i] = up[0] * p.x + up[1] * p.y + up[2] * p.z;
  }
  std::vector<double> sorted = h;
  std::sort(sorted.begin(), sorted.end());
  const double lo = sorted[n / 50], hi = sorted[n - 1 - n / 50];
  cv::Mat levels(1, int(n), CV_8UC1), colours;
  for (std::size_t i = 0; i < n; ++i) {
    const double t = hi > lo ? (h[i] - lo) / (hi - lo) : 0.5;
    levels.at<std::uint8_t>(0, int(i)) =
        cv::saturate_cast<std::uint8_t>(255 * std::clamp(t, 0.0, 1.0));
  }
  cv::applyColorMap(levels, colours, cv::COLORMAP_TURBO);
  auto cubes = COctoMapVoxels::Create();
  cubes->showGridLines(false);
  cubes->resizeVoxelSets(2);  // occupied, free (empty, hidden)
  cubes->reserveVoxels(mrpt::opengl::VOXEL_SET_OCCUPIED, n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto& p = map.points[i];
    const cv::Vec3b bgr = colours.at<cv::Vec3b>(0, int(i));
    cubes->push_back_Voxel(mrpt::opengl::VOXEL_SET_OCCUPIED,
                           COctoMapVoxels::TVoxel({p.x, p.y, p.z}, map.voxel_size,
                                                  mrpt::img::TColor(bgr[2], bgr[1], bgr[0])));
  }
  cubes->showVoxels(mrpt::opengl::VOXEL_SET_FREESPACE, false);
  // The renderer culls objects by their bounding box (default: the origin).
  const CloudBounds b = computeBounds(map.points);
  const double half = map.voxel_size / 2;
  cubes->setBoundingBox({b.min[0] - half, b.min[1] - half, b.min[2] - half},
                        {b.max[0] + half, b.max[1] + half, b.max[2] + half});
  return cubes;
}

}  // namespace

void MapRenderer::checkOptions(const RenderOptions& options) {
  if (options.width <= 0 || options.height <= 0 || options.width > 16384 ||
      options.height > 16384) {
    throw std::invalid_argument("render: image size must be 1..16384");
  }
  if (!(options.vertical_fov_deg > 1 && options.vertical_fov_deg < 170)) {
    throw std::invalid_argument("render: vertical FOV must be in (1, 170) degrees");
  }
  if (!(options.point_size > 0)) throw std::invalid_argument("render: point size must be > 0");
}

MapRenderer::MapRenderer(RenderOptions options) : options_(options) {
  checkOptions(options);
  context_ = std::make_unique<OffscreenContext>(options.width, options.height);
  mrpt::opengl::CFBORender::Parameters p(options.width, options.height);
  p.create_EGL_context = false;  // render into the OSMesa context made current above
  fbo_ = std::make_unique<mrpt::opengl::CFBORender>(p);
}

MapRenderer::~MapRenderer() {
  // The FBO's GL objects belong to our context: release them while current.
  if (context_) context_->makeCurrent();
  fbo_.reset();
}

PinholeCamera MapRenderer::intrinsics() const {
  PinholeCamera cam;
  cam.width = options_.width;
  cam.height = options_.height;
  cam.fy = 0.5 * options_.height / std::tan(0.5 * options_.vertical_fov_deg * M_PI / 180);
  cam.fx = cam.fy;
  cam.cx = 0.5 * options_.width;
  cam.cy = 0.5 * options_.height;
  cam.name = "render";
  return cam;
}

mrpt::poses::CPose3D MapRenderer::cameraPose(const MapData& map, const ViewSpec& view) const {
  if (view.kind == ViewSpec::Kind::kPose) return view.pose;
  const PinholeCamera K = intrinsics();
  const double hfov = 2 * std::atan(0.5 * K.width / K.fx);
  const double vfov = 2 * std::atan(0.5 * K.height / K.fy);
  return viewCameraPose(view, frameScene(map, options_.up), hfov, vfov);
}

bool MapRenderer::showsAnyPoint(const MapData& map, const mrpt::poses::CPose3D& camera_pose) const {
  float near_m = 0, far_m = 0;
  mrpt::opengl::COpenGLScene().getViewport()->getViewportClipDistances(near_m, far_m);
  const PinholeCamera K = intrinsics();
  for (const auto& p : map.points) {
    double x, y, z;
    camera_pose.inverseComposePoint(p.x, p.y, p.z, x, y, z);
    if (!(z >= near_m && z <= far_m)) continue;
    const double u = K.fx * x / z + K.cx, v = K.fy * y / z + K.cy;
    if (u >= 0 && u < K.width && v >= 0 && v < K.height) return true;
  }
  return false;
}

cv::Mat MapRenderer::render(const MapData& map, const ViewSpec& view) {
  return renderFromPose(map, cameraPose(map, view));
}

cv::Mat MapRenderer::renderFromPose(const MapData& map, const mrpt::poses::CPose3D& camera_pose) {
  using namespace mrpt::opengl;
  context_->makeCurrent();
  COpenGLScene scene;
  const auto& bg = options_.background;
  scene.getViewport()->setCustomBackgroundColor({bg[0] / 255.f, bg[1] / 255.f, bg[2] / 255.f, 1.f});

  if (map.voxel_size > 0 && !map.points.empty()) {
    scene.insert(voxelCubes(map, options_.up ? *options_.up : frameScene(map).up));
    // Mostly ambient light: the default light comes from above, which
    // leaves the faces that look at the camera nearly black.
    auto& light = scene.getViewport()->lightParameters();
    light.ambient = {0.6f, 0.6f, 0.6f, 1.0f};
    light.diffuse = {0.45f, 0.45f, 0.45f, 1.0f};
  } else {
    auto cloud = CPointCloudColoured::Create();
    cloud->enableVariablePointSize(false);
    cloud->setPointSize(options_.point_size);
    cloud->resize(map.points.size());
    for (std::size_t i = 0; i < map.points.size(); ++i) {
      const auto& p = map.points[i];
      cloud->setPoint_fast(i, mrpt::math::TPointXYZfRGBAu8(p.x, p.y, p.z, p.r, p.g, p.b, 255));
    }
    scene.insert(cloud);
  }

  if (options_.draw_trajectory && map.keyframes.size() >= 2) {
    auto lines = CSetOfLines::Create();
    lines->setColor_u8(220, 20, 20);
    lines->setLineWidth(2);
    for (std::size_t i = 0; i + 1 < map.keyframes.size(); ++i) {
      const auto& a = map.keyframes[i].pose;
      const auto& b = map.keyframes[i + 1].pose;
      lines->appendLine(a.x(), a.y(), a.z(), b.x(), b.y(), b.z());
    }
    scene.insert(lines);
  }
  if (options_.draw_frustums && !map.keyframes.empty()) {
    double depth = options_.frustum_depth;
    // The radius does not depend on up: skip the plane search for it.
    if (depth <= 0)
      depth = 0.06 * frameScene(map, options_.up.value_or(std::array<double, 3>{0, 0, 1})).radius;
    const auto to_optical = xForwardToOptical();
    for (const auto& kf : map.keyframes) {
      // 4:3 Kinect-like frustum (62 x 48 degrees).
      auto f = CFrustum::Create(0.f, float(depth), 62.f, 48.f, 2.f, true, false);
      f->setColor_u8(30, 60, 220);
      f->setPose(kf.pose + to_optical);
      scene.insert(f);
    }
  }

  const PinholeCamera K = intrinsics();
  auto& cam = fbo_->getCamera(scene);
  cam.setProjectiveFromPinhole(K.toMrpt());
  cam.set6DOFMode(true);
  cam.setPose(camera_pose);

  mrpt::img::CImage img;
  fbo_->render_RGB(scene, img);
  cv::Mat out = img.asCvMat<cv::Mat>(mrpt::img::DEEP_COPY);
  if (out.type() != CV_8UC3) throw std::runtime_error("render: unexpected image type");
  return out;
}

}  // namespace dynslam
