// The node as a long-running service (issue 65): bad messages are dropped,
// counted and named once, bad parameters stop it before it subscribes, and a
// SIGTERM saves the session.
#include <gtest/gtest.h>

#include "faults/fault_support.h"
#include "ros_master.h"
#include "ros_test_support.h"
