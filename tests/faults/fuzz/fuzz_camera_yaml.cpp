// libFuzzer target: a camera YAML as `run --camera`, `convert -c`, export
// and the node's _camera:= read it (lib/core/camera.h loadCameraYaml): the
// YAML checks and parse, then every key's type, value and range. Every input
// gives a camera or the reader's InputError, never a crash or a hang.
#include "core/camera.h"
#include "fuzz_input_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return dynslam::fuzz::readAsFile(data, size, ".yaml",
                                   [](const std::string& path) { dynslam::loadCameraYaml(path); });
}
