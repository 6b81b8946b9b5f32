#include "render/offscreen_context.h"

#include <GL/osmesa.h>

#include <stdexcept>
#include <string>

namespace dynslam {

OffscreenContext::OffscreenContext(int width, int height)
    : width_(width), height_(height), buffer_(std::size_t(width) * height * 4) {
  if (width <= 0 || height <= 0) throw std::invalid_argument("OffscreenContext: bad size");
  const int attribs[] = {OSMESA_FORMAT,
                         OSMESA_RGBA,
                         OSMESA_DEPTH_BITS,
                         24,
                         OSMESA_PROFILE,
                         OSMESA_CORE_PROFILE,
                         OSMESA_CONTEXT_MAJOR_VERSION,
                         3,
                         OSMESA_CONTEXT_MINOR_VERSION,
                         3,
                         0};
  OSMesaContext ctx = OSMesaCreateContextAttribs(attribs, nullptr);
  if (!ctx) throw std::runtime_error("OSMesa: cannot create a GL 3.3 core context");
  context_ = ctx;
  makeCurrent();
  // gl* calls (ours and MRPT's) bind to whichever loaded library exports
  // them first. If that is glvnd's libOpenGL instead of OSMesa, there is no
  // current context for it and every call silently does nothing: fail here
  // with the fix instead of rendering blank images.
  if (glGetString(GL_RENDERER) == nullptr) {
    OSMesaDestroyContext(ctx);
    context_ = nullptr;
    throw std::runtime_error(
        "OpenGL calls do not reach OSMesa: link libOSMesa before mrpt::opengl and "
        "libOpenGL/libGL (link dynslam_render, whose first dependency is OSMesa)");
  }
}

OffscreenContext::~OffscreenContext() {
  if (context_) OSMesaDestroyContext(static_cast<OSMesaContext>(context_));
}

void OffscreenContext::makeCurrent() {
  if (!OSMesaMakeCurrent(static_cast<OSMesaContext>(context_), buffer_.data(), GL_UNSIGNED_BYTE,
                         width_, height_)) {
    throw std::runtime_error("OSMesa: cannot make the context current");
  }
}

const char* OffscreenContext::renderer() const {
  const auto* s = glGetString(GL_RENDERER);
  return s ? reinterpret_cast<const char*>(s) : "unknown";
}

}  // namespace dynslam
