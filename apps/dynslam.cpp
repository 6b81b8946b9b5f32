// `dynslam`: the single user-facing command. All logic lives in lib/cli.
#include "cli/commands.h"

int main(int argc, char** argv) { return dynslam::cli::dispatch(argc, argv); }
