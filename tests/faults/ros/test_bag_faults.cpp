// Damaged and odd ROS bags given to `run` and `convert` (issue 65): each must
// end in one line naming the bag (and topic), the right exit code and nothing
// half-written; none may crash the reader.
#include <gtest/gtest.h>

#include "faults/fault_support.h"
#include "ros_test_support.h"
