#include "rawlog/mrpt_images_base.h"

#include <mrpt/img/CImage.h>

namespace dynslam {

namespace {
std::mutex& baseMutex() {
  static std::mutex m;
  return m;
}
}  // namespace

ImagesBaseScope::ImagesBaseScope(const std::string& dir)
    : lock_(baseMutex()), saved_(mrpt::img::CImage::getImagesPathBase()) {
  mrpt::img::CImage::setImagesPathBase(dir);
}

ImagesBaseScope::~ImagesBaseScope() { mrpt::img::CImage::setImagesPathBase(saved_); }

}  // namespace dynslam
