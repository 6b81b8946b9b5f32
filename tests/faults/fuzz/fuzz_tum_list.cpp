// libFuzzer target: a TUM rgb.txt / depth.txt list (rawlog/sequence_source.h
// readTumList), and the pairing of a list with itself.
#include "fuzz_input_file.h"
#include "rawlog/sequence_source.h"
#include "rawlog/tum_folder_source.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return dynslam::fuzz::readAsFile(data, size, ".txt", [](const std::string& path) {
    const auto list = dynslam::readTumList(path);
    dynslam::associateTumLists(list, list);
  });
}
