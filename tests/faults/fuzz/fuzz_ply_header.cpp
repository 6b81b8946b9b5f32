// libFuzzer target: the PLY header check render and export run before PCL
// reads a file (lib/mapexport/ply_check.h).
#include "fuzz_input_file.h"
#include "mapexport/ply_check.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return dynslam::fuzz::readAsFile(data, size, ".ply",
                                   [](const std::string& path) { dynslam::checkPlyFile(path); });
}
