#include "bench/run_outputs.h"

#include <vector>

#include "core/errors.h"
#include "core/text_table.h"

namespace dynslam {

FrameTimes readFrameTimes(const std::string& path) {
  FrameTimes ft;
  forEachDataLine(path, [&](const TextLine& line) {
    if (line.size() != 3) line.fail("expected 'timestamp track_ms frame_total_ms'");
    ft.timestamps.push_back(line.number(0));
    ft.track_ms.push_back(line.number(1));
    ft.frame_ms.push_back(line.number(2));
  });
  return ft;
}

}  // namespace dynslam
