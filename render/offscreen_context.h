#pragma once
// An OpenGL context without a display: Mesa's OSMesa (llvmpipe software
// rasteriser), so snapshots work on headless CI machines and give the same
// pixels on every run on one machine. MRPT's CFBORender would create an EGL
// context, which needs a GPU driver; instead we create a GL 3.3 core context
// here, make it current, and let CFBORender render into its own framebuffer
// object inside it.
#include <cstdint>
#include <vector>

namespace dynslam {

class OffscreenContext {
 public:
  /// Creates and makes current a GL >= 3.3 core context with a
  /// width x height RGBA buffer. Throws std::runtime_error if OSMesa fails.
  OffscreenContext(int width, int height);
  ~OffscreenContext();
  OffscreenContext(const OffscreenContext&) = delete;
  OffscreenContext& operator=(const OffscreenContext&) = delete;

  /// Makes this context current on the calling thread again.
  void makeCurrent();
  /// GL_RENDERER string (e.g. "llvmpipe (LLVM 15.0.6, 256 bits)").
  const char* renderer() const;

 private:
  void* context_ = nullptr;  ///< OSMesaContext (kept opaque: no GL headers here)
  int width_, height_;
  std::vector<std::uint8_t> buffer_;
};

}  // namespace dynslam
