#include <stdexcept>

#include "cli/commands.h"

namespace dynslam::cli {

int convertMain(int, char**) { throw std::runtime_error("not implemented yet"); }

}  // namespace dynslam::cli
