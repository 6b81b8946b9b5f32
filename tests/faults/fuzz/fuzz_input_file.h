#pragma once
// The readers fuzzed here take a path, as the commands give them: each
// input is written to one scratch file per fuzzing process, read back by
// the reader, and only InputError (the reader refusing the file, naming it)
// may come out; anything else escaping, a crash or a sanitizer report is a
// finding.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include "core/errors.h"

namespace dynslam::fuzz {

/// The scratch file of this process ($TMPDIR or /tmp), `suffix` its ending.
inline const std::string& scratchFile(const char* suffix) {
  static const std::string path = [&] {
    const char* tmp = std::getenv("TMPDIR");
    return std::string(tmp && *tmp ? tmp : "/tmp") + "/dynslam_fuzz_" + std::to_string(::getpid()) +
           suffix;
  }();
  return path;
}

/// Writes the input to the scratch file and calls read(path), taking an
/// InputError as the reader's answer.
template <class Read>
int readAsFile(const std::uint8_t* data, std::size_t size, const char* suffix, Read&& read) {
  const std::string& path = scratchFile(suffix);
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  try {
    read(path);
  } catch (const InputError&) {
  }
  return 0;
}

}  // namespace dynslam::fuzz
