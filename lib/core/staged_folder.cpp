#include "core/staged_folder.h"

#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>

#include "core/errors.h"

namespace dynslam {
namespace fs = std::filesystem;
namespace {

const char* const kStagingTag = ".partial-";

// ".NAME.partial-PID" beside the folder NAME.
fs::path stagingPath(const fs::path& final_dir, long pid) {
  return final_dir.parent_path() /
         ("." + final_dir.filename().string() + kStagingTag + std::to_string(pid));
}

// Staging folders of processes that no longer exist (killed by a second
// Ctrl-C or SIGKILL before they could clean up).
void removeStaleStaging(const fs::path& final_dir) {
  const std::string prefix = "." + final_dir.filename().string() + kStagingTag;
  std::error_code ec;
  fs::path parent = final_dir.parent_path();
  if (parent.empty()) parent = ".";
  for (const auto& e : fs::directory_iterator(parent, ec)) {
    const std::string name = e.path().filename().string();
    if (name.rfind(prefix, 0) != 0) continue;
    char* end = nullptr;
    const long pid = std::strtol(name.c_str() + prefix.size(), &end, 10);
    if (pid <= 0 || *end != '\0') continue;
    if (::kill(pid_t(pid), 0) == 0 || errno != ESRCH) continue;  // still running
    std::error_code rm;
    fs::remove_all(e.path(), rm);
  }
}

}  // namespace

namespace {
bool hasPrefix(const fs::path& p, const fs::path& prefix) {
  auto pi = p.begin();
  for (auto fi = prefix.begin(); fi != prefix.end(); ++fi, ++pi) {
    if (fi->empty()) continue;  // a trailing separator
    if (pi == p.end() || *pi != *fi) return false;
  }
  return true;
}
}  // namespace

bool isInsideFolder(const std::string& path, const std::string& folder) {
  std::error_code ec;
  const fs::path p = fs::absolute(path, ec).lexically_normal();
  const fs::path f = fs::absolute(folder, ec).lexically_normal();
  if (ec || f.empty()) return false;
  // As written (a link to the input inside the folder is deleted with it)
  // and with links resolved (a link to the folder).
  return hasPrefix(p, f) || hasPrefix(fs::weakly_canonical(p, ec), fs::weakly_canonical(f, ec));
}

void checkOutputFolder(const std::string& dir, const std::vector<std::string>& markers) {
  std::error_code ec;
  const fs::path f(dir);
  if (!fs::exists(f, ec)) return;
  if (!fs::is_directory(f, ec)) throw InputError(dir, "exists and is not a folder");
  // An earlier output has every marker file (one of them alone is any
  // project's report.json: replacing that folder deleted it, found by
  // fuzzing).
  bool empty = fs::is_empty(f, ec), ours = !markers.empty();
  for (const auto& m : markers) ours = ours && fs::is_regular_file(f / m, ec);
  if (!empty && !ours)
    throw InputError(dir,
                     "folder is not empty and holds no earlier output to replace; "
                     "choose an empty or new folder");
}

StagedFolder::StagedFolder(std::string final_dir, const std::vector<std::string>& markers) {
  fs::path f(final_dir);
  if (f.filename().empty()) f = f.parent_path();  // "out/" -> "out"
  std::error_code ec;
  // A link to an earlier output: that output is replaced and the link kept
  // (replacing the link would leave the old run where the link pointed).
  if (fs::is_symlink(f, ec) && fs::is_directory(f, ec)) f = fs::canonical(f, ec);
  final_ = f.string();
  checkOutputFolder(final_, markers);
  const fs::path parent = f.parent_path().empty() ? fs::path(".") : f.parent_path();
  fs::create_directories(parent, ec);
  if (ec || !fs::is_directory(parent)) throw InputError(parent.string(), "cannot create folder");
  lock_ = std::make_unique<OutputLock>(final_);
  const fs::path s = stagingPath(f, long(::getpid()));
  removeStaleStaging(f);
  fs::remove_all(s, ec);
  if (!fs::create_directory(s, ec))
    throw InputError(s.string(), "cannot create folder: " + ec.message());
  staging_ = s.string();
}

StagedFolder::~StagedFolder() {
  std::error_code ec;
  if (!committed_ && !staging_.empty()) fs::remove_all(staging_, ec);
}

void StagedFolder::commit() {
  const fs::path f(final_), s(staging_);
  std::error_code ec;
  // Move an earlier output aside first: the final name then holds either
  // the old folder or the new one, never a mixture.
  fs::path old;
  if (fs::exists(f, ec)) {
    old = f.parent_path() / ("." + f.filename().string() + ".old-" + std::to_string(::getpid()));
    fs::remove_all(old, ec);
    fs::rename(f, old, ec);
    if (ec) throw InputError(final_, "cannot replace the earlier output: " + ec.message());
  }
  fs::rename(s, f, ec);
  if (ec) {
    std::error_code back;
    if (!old.empty()) fs::rename(old, f, back);
    throw InputError(final_, "cannot move the finished output into place: " + ec.message());
  }
  committed_ = true;
  if (!old.empty()) fs::remove_all(old, ec);
}

}  // namespace dynslam
