#include "core/atomic_file.h"

#include "core/errors.h"

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace dynslam {
namespace fs = std::filesystem;

namespace {
std::string tempNameFor(const std::string& final_path) {
  static std::atomic<unsigned> counter{0};
  const fs::path p(final_path);
  const std::string name = "." + p.filename().string() + ".tmp" + std::to_string(::getpid()) + "_" +
                           std::to_string(counter++);
  return (p.parent_path() / name).string();
}
}  // namespace

AtomicPath::AtomicPath(std::string final_path)
    : final_(std::move(final_path)), tmp_(tempNameFor(final_)) {}

AtomicPath::~AtomicPath() {
  if (!committed_) {
    std::error_code ec;
    fs::remove(tmp_, ec);
  }
}

void AtomicPath::commit() {
  std::error_code ec;
  fs::rename(tmp_, final_, ec);
  if (ec) {
    throw std::runtime_error(final_ + ": cannot write (" + ec.message() + ")");
  }
  committed_ = true;
}

void writeFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& writer,
                         bool binary) {
  AtomicPath out(path);
  out.write(writer, binary);
  out.commit();
}

void AtomicPath::write(const std::function<void(std::ostream&)>& writer, bool binary) const {
  std::ofstream f(tmp_, binary ? std::ios::binary : std::ios::out);
  if (!f) throw std::runtime_error(final_ + ": cannot open for writing");
  writer(f);
  errno = 0;
  f.close();  // flushes: a full disk shows here, not in the writes
  if (!f) {
    const std::string why = errno ? std::strerror(errno) : "disk full?";
    throw std::runtime_error(final_ + ": write failed (" + why + ")");
  }
}

bool fileExists(const std::string& path) {
  std::error_code ec;
  return fs::is_regular_file(path, ec);
}

std::string regularFileProblem(const std::string& path, const std::string& what) {
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (fs::is_regular_file(st)) return "";
  if (!fs::exists(st)) return what + " not found";
  if (fs::is_directory(st)) return "is a folder, expected a " + what;
  return "not a regular file (a device or a pipe), expected a " + what;
}

void requireRegularFile(const std::string& path, const std::string& what) {
  const std::string problem = regularFileProblem(path, what);
  if (!problem.empty()) throw InputError(path, problem);
}

std::string readRegularFile(const std::string& path, const std::string& what,
                            std::uint64_t max_bytes) {
  requireRegularFile(path, what);
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) throw InputError(path, "cannot open " + what);
  const std::uint64_t size = static_cast<std::uint64_t>(in.tellg());
  if (size > max_bytes)
    throw InputError(path, what + " of " + std::to_string(size) + " bytes is too large (at most " +
                               std::to_string(max_bytes) + ")");
  in.seekg(0);
  std::string bytes(static_cast<std::size_t>(size), '\0');
  in.read(bytes.data(), static_cast<std::streamsize>(size));
  if (in.gcount() != static_cast<std::streamsize>(size))
    throw InputError(path, "cannot read " + what);
  return bytes;
}

bool isDirectory(const std::string& path) {
  std::error_code ec;
  return fs::is_directory(path, ec);
}

void makeDirectories(const std::string& path) {
  std::error_code ec;
  fs::create_directories(path, ec);
  if (ec || !isDirectory(path)) {
    throw std::runtime_error(path + ": cannot create directory (" + ec.message() + ")");
  }
}

}  // namespace dynslam
