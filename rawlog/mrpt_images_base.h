#pragma once
// MRPT resolves relative external image/matrix file names against one
// process-wide folder (mrpt::img::CImage::setImagesPathBase). Code that reads
// or writes external data holds an ImagesBaseScope so that two rawlogs used at
// once (or a conversion next to a reader) never see each other's folder.
#include <mutex>
#include <string>

namespace dynslam {

class ImagesBaseScope {
 public:
  /// Locks the process-wide base and points it at `dir` until destruction.
  explicit ImagesBaseScope(const std::string& dir);
  ~ImagesBaseScope();
  ImagesBaseScope(const ImagesBaseScope&) = delete;
  ImagesBaseScope& operator=(const ImagesBaseScope&) = delete;

 private:
  std::unique_lock<std::mutex> lock_;
  std::string saved_;
};

}  // namespace dynslam
