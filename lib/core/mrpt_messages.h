#pragma once
// MRPT exceptions carry a multi-line trace ("file:line: function: ...");
// user-facing errors must stay on one line.
#include <cstddef>
#include <string>

namespace dynslam {

/// The most informative single line of an exception message from MRPT.
std::string oneLineMessage(const std::string& what);

/// Length of the valid UTF-8 sequence of two to four bytes starting at
/// s[i], 0 if none starts there.
std::size_t utf8SequenceAt(const std::string& s, std::size_t i);
/// Offset of the first byte of `s` that is not part of valid UTF-8, npos
/// when all of it is.
std::size_t firstInvalidUtf8(const std::string& s);

/// `line` safe to print on a terminal: control bytes and bytes that are not
/// UTF-8 (a message that quotes a binary file's bytes) as \xNN, and at most
/// `max_chars` characters: a longer line loses its middle ("head...tail",
/// a quarter before, three quarters after), so the reason at its end stays.
std::string printableLine(const std::string& line, std::size_t max_chars = 2000);

}  // namespace dynslam
