#pragma once
// Quoting for command lines that a POSIX shell will read (the benchmark's
// emitted job file, the tests' commands): any byte string becomes one word.
#include <string>

namespace dynslam {

/// 'text' for /bin/sh: single-quoted, a ' inside written as '\''.
std::string shellQuote(const std::string& text);

}  // namespace dynslam
