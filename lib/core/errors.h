#pragma once
// Errors that reach the user. Every bad-input failure names the file (and the
// line, for text files) so a user can fix the data without reading our code.
#include <stdexcept>
#include <string>

namespace dynslam {

/// Bad input data or configuration: message formatted as "FILE:LINE: what"
/// (or "FILE: what" when no line applies).
class InputError : public std::runtime_error {
 public:
  InputError(const std::string& file, const std::string& what)
      : std::runtime_error(file + ": " + what), file_(file) {}
  InputError(const std::string& file, std::size_t line, const std::string& what)
      : std::runtime_error(file + ":" + std::to_string(line) + ": " + what),
        file_(file),
        line_(line) {}

  const std::string& file() const { return file_; }
  /// 0 when the error is not tied to a line.
  std::size_t line() const { return line_; }

 private:
  std::string file_;
  std::size_t line_ = 0;
};

/// A bad command-line value found after the arguments were parsed (a range,
/// a malformed list, an unknown extension): the dispatcher exits with the
/// usage code 2, as for TCLAP's own errors, instead of 1 (bad files, failures).
class UsageError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

}  // namespace dynslam
