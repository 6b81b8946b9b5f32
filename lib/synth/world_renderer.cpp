#include "synth/world_renderer.h"

#include <mrpt/img/CImage.h>
#include <mrpt/opengl/CFBORender.h>
#include <mrpt/opengl/COpenGLScene.h>
#include <mrpt/opengl/CSetOfObjects.h>
#include <mrpt/opengl/CTexturedPlane.h>

#include <stdexcept>

#include "render/offscreen_context.h"

namespace dynslam::synth {

namespace {

constexpr double kGlPixelShiftX = 0.5, kGlPixelShiftY = 0.5;

std::shared_ptr<mrpt::opengl::CSetOfObjects> objectsOf(const std::vector<TexturedQuad>& quads) {
  auto set = mrpt::opengl::CSetOfObjects::Create();
  for (const TexturedQuad& q : quads) {
    auto plane = mrpt::opengl::CTexturedPlane::Create(-q.width / 2, q.width / 2, -q.height / 2,
                                                      q.height / 2);
    cv::Mat upright;  // image row 0 at the quad's top (local +y)
    cv::flip(q.texture, upright, 0);
    plane->assignImage(mrpt::img::CImage(upright, mrpt::img::DEEP_COPY));
    plane->enableTextureLinearInterpolation(true);
    plane->setPose(q.pose);
    set->insert(plane);
  }
  return set;
}

cv::Mat toCv(const mrpt::math::CMatrixFloat& d) {
  cv::Mat out(static_cast<int>(d.rows()), static_cast<int>(d.cols()), CV_32F);
  for (int r = 0; r < out.rows; ++r)
    for (int c = 0; c < out.cols; ++c) out.at<float>(r, c) = d(r, c);
  return out;
}

}  // namespace

WorldRenderer::WorldRenderer(const RoomWorld& world, const PinholeCamera& camera)
    : world_(world), camera_(camera) {
  if (camera.hasDistortion())
    throw std::invalid_argument("synth: the render camera has no distortion");
  context_ = std::make_unique<OffscreenContext>(camera.width, camera.height);
  mrpt::opengl::CFBORender::Parameters p(camera.width, camera.height);
  p.create_EGL_context = false;  // render into the OSMesa context made current above
  fbo_ = std::make_unique<mrpt::opengl::CFBORender>(p);
  scene_ = std::make_unique<mrpt::opengl::COpenGLScene>();
  scene_->getViewport()->setViewportClipDistances(0.05f, 30.f);
  statics_ = objectsOf(world.statics);
  scene_->insert(statics_);
  for (const auto& faces : world.mover_faces) {
    movers_.push_back(objectsOf(faces));
    scene_->insert(movers_.back());
  }
  auto& cam = fbo_->getCamera(*scene_);
  // OpenGL puts pixel (u, v)'s centre at u + 0.5, v + 0.5 from the corner;
  // OpenCV at u, v: shift the principal point so that the rendered image is
  // the one `camera` sees (checked against a ray cast in the tests).
  mrpt::img::TCamera K = camera.toMrpt();
  K.cx(camera.cx + kGlPixelShiftX);
  K.cy(camera.cy + kGlPixelShiftY);
  cam.setProjectiveFromPinhole(K);
  cam.set6DOFMode(true);
}

WorldRenderer::~WorldRenderer() {
  // The FBO's GL objects belong to our context: release them while current.
  if (context_) context_->makeCurrent();
  scene_.reset();
  fbo_.reset();
}

cv::Mat WorldRenderer::depthOf(const mrpt::opengl::COpenGLScene& scene) {
  mrpt::math::CMatrixFloat d;
  fbo_->render_depth(scene, d);
  return toCv(d);
}

RenderedView WorldRenderer::render(const mrpt::poses::CPose3D& camera_wc, double t) {
  context_->makeCurrent();
  for (std::size_t k = 0; k < movers_.size(); ++k) {
    movers_[k]->setPose(world_.movers[k].poseAt(t));
    movers_[k]->setVisibility(true);
  }
  statics_->setVisibility(true);
  fbo_->getCamera(*scene_).setPose(camera_wc);

  RenderedView v;
  mrpt::img::CImage rgb;
  mrpt::math::CMatrixFloat d;
  fbo_->render_RGBD(*scene_, rgb, d);
  v.rgb = rgb.asCvMat<cv::Mat>(mrpt::img::DEEP_COPY);
  if (v.rgb.type() != CV_8UC3) throw std::runtime_error("synth: unexpected rendered image type");
  v.depth = toCv(d);
  if (movers_.empty()) return v;

  // Mover k's pixels: where it alone gives the depth the whole scene has.
  v.mask = cv::Mat(v.depth.size(), CV_8U, cv::Scalar(0));
  statics_->setVisibility(false);
  for (std::size_t k = 0; k < movers_.size(); ++k) {
    for (std::size_t j = 0; j < movers_.size(); ++j) movers_[j]->setVisibility(j == k);
    const cv::Mat dk = depthOf(*scene_);
    for (int r = 0; r < dk.rows; ++r)
      for (int c = 0; c < dk.cols; ++c) {
        const float a = dk.at<float>(r, c), b = v.depth.at<float>(r, c);
        if (a > 0 && std::abs(a - b) <= 1e-3f * b + 1e-4f)
          v.mask.at<uint8_t>(r, c) = static_cast<uint8_t>(k + 1);
      }
  }
  statics_->setVisibility(true);
  for (auto& m : movers_) m->setVisibility(true);
  return v;
}

}  // namespace dynslam::synth
