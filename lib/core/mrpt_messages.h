#pragma once
// MRPT exceptions carry a multi-line trace ("file:line: function: ...");
// user-facing errors must stay on one line.
#include <string>

namespace dynslam {

/// The most informative single line of an exception message from MRPT.
std::string oneLineMessage(const std::string& what);

}  // namespace dynslam
