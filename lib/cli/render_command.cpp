#include <stdexcept>

#include "cli/commands.h"

namespace dynslam::cli {

int renderMain(int, char**) { throw std::runtime_error("not implemented yet"); }

}  // namespace dynslam::cli
