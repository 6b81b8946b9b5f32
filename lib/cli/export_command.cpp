#include <stdexcept>

#include "cli/commands.h"

namespace dynslam::cli {

int exportMain(int, char**) { throw std::runtime_error("not implemented yet"); }

}  // namespace dynslam::cli
