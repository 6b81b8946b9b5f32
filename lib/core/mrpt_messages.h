#pragma once
// MRPT exceptions carry a multi-line trace ("file:line: function: ...");
// user-facing errors must stay on one line.
#include <cstddef>
#include <string>

namespace dynslam {

/// The most informative single line of an exception message from MRPT.
std::string oneLineMessage(const std::string& what);

/// `line` safe to print on a terminal: control bytes and bytes that are not
/// UTF-8 (a message that quotes a binary file's bytes) as \xNN, and at most
/// `max_chars` characters: a longer line loses its middle ("head...tail",
/// a quarter before, three quarters after), so the reason at its end stays.
std::string printableLine(const std::string& line, std::size_t max_chars = 2000);

}  // namespace dynslam
