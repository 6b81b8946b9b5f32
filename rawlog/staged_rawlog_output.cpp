#include "rawlog/staged_rawlog_output.h"

#include <unistd.h>

#include <filesystem>
#include <stdexcept>

#include "core/errors.h"
#include "rawlog/rawlog_layout.h"

namespace dynslam {
namespace fs = std::filesystem;

namespace {
std::string hiddenSibling(const std::string& path, const std::string& tag) {
  const fs::path p(path);
  return (p.parent_path() / ("." + p.filename().string() + "." + tag + std::to_string(::getpid())))
      .string();
}

const std::string& checkedRawlogPath(const std::string& path) {
  const fs::path p(path);
  if (p.extension() != ".rawlog") throw InputError(path, "output name must end in .rawlog");
  if (isDirectory(path)) throw InputError(path, "is a folder, expected a .rawlog file name");
  const fs::path parent = p.parent_path().empty() ? fs::path(".") : p.parent_path();
  if (!isDirectory(parent.string()))
    throw InputError(path, "output folder '" + parent.string() + "' does not exist");
  return path;
}
}  // namespace

StagedRawlogOutput::StagedRawlogOutput(const std::string& final_rawlog)
    : rawlog_(checkedRawlogPath(final_rawlog)),
      groundtruth_(rawlogGroundtruthPath(final_rawlog)),
      images_(rawlogImagesDir(final_rawlog)),
      tmp_images_(hiddenSibling(images_, "tmp")) {
  std::error_code ec;
  fs::remove_all(tmp_images_, ec);
  makeDirectories(tmp_images_);
}

StagedRawlogOutput::~StagedRawlogOutput() {
  if (!committed_) {
    std::error_code ec;
    fs::remove_all(tmp_images_, ec);
  }
}

void StagedRawlogOutput::commit(bool with_groundtruth) {
  const std::string backup = hiddenSibling(images_, "old");
  std::error_code ec;
  fs::remove_all(backup, ec);
  const bool had_images = fs::exists(images_, ec);
  auto fail = [&](const std::string& what) {
    throw std::runtime_error(images_ + ": cannot move the converted images into place (" + what +
                             ")");
  };
  if (had_images) {
    fs::rename(images_, backup, ec);
    if (ec) fail(ec.message());
  }
  fs::rename(tmp_images_, images_, ec);
  if (ec) {
    const std::string msg = ec.message();
    if (had_images) fs::rename(backup, images_, ec);
    fail(msg);
  }
  try {
    rawlog_.commit();
  } catch (...) {
    fs::rename(images_, tmp_images_, ec);  // removed by the destructor
    if (had_images) fs::rename(backup, images_, ec);
    throw;
  }
  committed_ = true;
  if (with_groundtruth) {
    groundtruth_.commit();
  } else {
    fs::remove(groundtruth_.finalPath(), ec);  // belonged to the replaced rawlog
  }
  fs::remove_all(backup, ec);
}

}  // namespace dynslam
