#pragma once
// One-line progress display ("frame 120/694  31.2 fps  ETA 18 s") on stderr,
// only when stderr is a terminal so that logs and CI output stay clean.
#include <chrono>
#include <string>

namespace dynslam {

class ProgressLine {
 public:
  ProgressLine(std::string label, std::size_t total);
  /// Reports `done` items; redraws at most ~5 times a second.
  void update(std::size_t done, const std::string& extra = "");
  /// Ends the line (newline) if anything was drawn.
  void finish();
  bool enabled() const { return enabled_; }

 private:
  std::string label_;
  std::size_t total_;
  bool enabled_;
  bool drawn_ = false;
  std::chrono::steady_clock::time_point start_, last_;
};

}  // namespace dynslam
