#pragma once
// The `dynslam` subcommands. Each one parses its own arguments (TCLAP, shipped
// with MRPT) and calls into the libraries; apps/dynslam.cpp only dispatches.
#include <string>
#include <vector>

namespace TCLAP {
class CmdLine;
}

namespace dynslam::cli {

/// Exit codes shared by all subcommands.
enum ExitCode : int { kOk = 0, kFailure = 1, kUsage = 2 };

struct Subcommand {
  std::string name;
  std::string summary;
  /// argv[0] is "dynslam NAME".
  int (*main)(int argc, char** argv);
};

const std::vector<Subcommand>& subcommands();

/// Parses a subcommand's arguments with MRPT's TCLAP (which prints the help or
/// the error itself). Returns true to go on; false with `exit_code` set to 0
/// after --help/--version, or kUsage after an argument error.
bool parseArguments(TCLAP::CmdLine& cmd, int argc, char** argv, int& exit_code);

/// Runs `dynslam ARGS`: picks the subcommand, turns exceptions into a one-line
/// "dynslam NAME: error: ..." on stderr and exit code 2 (UsageError: a bad
/// command-line value) or 1 (anything else: bad files, runtime failures).
int dispatch(int argc, char** argv);

// Subcommand entry points (one file each in this folder).
int convertMain(int argc, char** argv);
int runMain(int argc, char** argv);
int evalMain(int argc, char** argv);
int exportMain(int argc, char** argv);
int renderMain(int argc, char** argv);
int vocabMain(int argc, char** argv);
int benchMain(int argc, char** argv);
int synthMain(int argc, char** argv);
int configMain(int argc, char** argv);

}  // namespace dynslam::cli
