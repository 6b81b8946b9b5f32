#pragma once
// Line-oriented reader for the whitespace-separated text lists of the TUM
// format (rgb.txt, depth.txt, groundtruth.txt, trajectories). Centralises the
// "FILE:LINE: what" error messages so every list reader reports alike.
#include <functional>
#include <string>
#include <vector>

namespace dynslam {

class TextLine {
 public:
  TextLine(const std::string& file, std::size_t number, std::vector<std::string> fields)
      : file_(file), number_(number), fields_(std::move(fields)) {}

  std::size_t number() const { return number_; }
  const std::string& file() const { return file_; }
  std::size_t size() const { return fields_.size(); }
  const std::string& field(std::size_t i) const { return fields_.at(i); }
  /// Parses fields [0, n) as doubles, requiring min_fields <= size();
  /// max_fields caps how many are parsed (extra fields are an error when
  /// strict). Throws InputError with file and line otherwise.
  std::vector<double> numbers(std::size_t min_fields, std::size_t max_fields) const;
  double number(std::size_t i) const;
  /// Throws InputError(file, line, what).
  [[noreturn]] void fail(const std::string& what) const;

 private:
  const std::string& file_;
  std::size_t number_;
  std::vector<std::string> fields_;
};

/// Calls fn for every non-blank line not starting with '#'.
/// Throws InputError(path, "cannot open") if the file cannot be read.
void forEachDataLine(const std::string& path, const std::function<void(const TextLine&)>& fn);

}  // namespace dynslam
