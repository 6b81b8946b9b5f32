// libFuzzer target: a config or camera YAML file as every command loads it
// (lib/core/config_reader.h loadYamlFile): the duplicate-key scan and the
// text pre-check, then MRPT's parser on what they let through, which must
// neither crash nor print past the capture.
#include "core/config_reader.h"
#include "fuzz_input_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return dynslam::fuzz::readAsFile(data, size, ".yaml",
                                   [](const std::string& path) { dynslam::loadYamlFile(path); });
}
