#pragma once
// Output files are written under a temporary name in the same folder and
// renamed into place only when complete, so an interrupted or failed run never
// leaves a half-written trajectory, report or map that looks valid.
#include <cstdint>
#include <functional>
#include <limits>
#include <ostream>
#include <string>

namespace dynslam {

/// Temporary sibling path for `final_path`; renamed onto it by commit().
/// If destroyed without commit() the temporary file is removed.
/// Use it with writers that take a path (PCL, assimp, OpenCV, MRPT).
class AtomicPath {
 public:
  explicit AtomicPath(std::string final_path);
  ~AtomicPath();
  AtomicPath(const AtomicPath&) = delete;
  AtomicPath& operator=(const AtomicPath&) = delete;

  /// Where the writer should write.
  const std::string& tmp() const { return tmp_; }
  /// Writes tmp() through a stream callback (not yet committed); throws
  /// std::runtime_error naming the final path if it cannot be written.
  void write(const std::function<void(std::ostream&)>& writer, bool binary = false) const;
  const std::string& finalPath() const { return final_; }
  /// Renames tmp() onto the final path; throws std::runtime_error on failure.
  void commit();

 private:
  std::string final_;
  std::string tmp_;
  bool committed_ = false;
};

/// Writes a text/binary file atomically through a stream callback.
/// Throws std::runtime_error naming the path if the file cannot be written.
void writeFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& writer,
                         bool binary = false);

bool fileExists(const std::string& path);
bool isDirectory(const std::string& path);
/// Throws InputError(path) unless path is a regular file: "WHAT not found",
/// "is a folder, expected a WHAT", or "not a regular file (a device or a
/// pipe), expected a WHAT" (/dev/null was "not found"; /dev/zero was read
/// until memory ran out).
void requireRegularFile(const std::string& path, const std::string& what = "file");
/// What requireRegularFile would say about `path` ("" for a regular file),
/// for errors that name another file (the list that holds the path).
std::string regularFileProblem(const std::string& path, const std::string& what = "file");
/// The whole of a regular file (requireRegularFile, naming it `what`), read
/// in one call. Throws InputError(path) if it cannot be opened or read, or
/// holds more than max_bytes ("WHAT of N bytes is too large"; checked from
/// its size, before anything is read).
std::string readRegularFile(const std::string& path, const std::string& what,
                            std::uint64_t max_bytes = std::numeric_limits<std::uint64_t>::max());
/// Creates the directory and its parents; throws naming the path on failure.
void makeDirectories(const std::string& path);

}  // namespace dynslam
