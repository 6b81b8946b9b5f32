#include "cli/commands.h"

#include <mrpt/3rdparty/tclap/CmdLine.h>

#include <cstdio>
#include <cstring>
#include <exception>
#include <memory>
#include <string>
#include <vector>

#include "core/errors.h"
#include "core/interrupt.h"
#include "core/log.h"
#include "core/mrpt_messages.h"

namespace dynslam::cli {

const std::vector<Subcommand>& subcommands() {
  static const std::vector<Subcommand> cmds = {
      {"convert", "convert a TUM RGB-D sequence folder into an MRPT rawlog", convertMain},
      {"run", "run SLAM on a TUM folder or rawlog; writes trajectory, keyframes, report", runMain},
      {"eval", "ATE / RPE / coverage of an estimated trajectory against groundtruth", evalMain},
      {"export", "fuse a run's static keyframes into a dense map (PLY or glTF .glb)", exportMain},
      {"render", "render an off-screen snapshot (PNG) of a map", renderMain},
      {"vocab", "train an ORB bag-of-words vocabulary, or describe one", vocabMain},
      {"bench", "benchmark suite: sequences x modes x runs, Markdown/JSON report, plots",
       benchMain},
      {"config", "print the effective config (every key, defaults filled in) as YAML", configMain},
      {"synth", "render a synthetic RGB-D sequence with known poses (TUM folder)", synthMain},
  };
  return cmds;
}

namespace {
/// TCLAP's usual output, except that a parse error is one "PROG: error: ..."
/// line plus a hint, and is remembered: MRPT's TCLAP returns false from
/// parse() both after --help and after an error.
class ArgumentOutput : public TCLAP::StdOutput {
 public:
  void failure(TCLAP::CmdLineInterface& c, TCLAP::ArgException& e) override {
    failed = true;
    std::string id = e.argId();  // "Argument: (--x, --name)" or blank
    if (id.find_first_not_of(' ') == std::string::npos) id.clear();
    std::fprintf(stderr, "%s: error: %s%s%s\nrun '%s --help' for usage\n",
                 c.getProgramName().c_str(), e.error().c_str(), id.empty() ? "" : " - ", id.c_str(),
                 c.getProgramName().c_str());
  }
  bool failed = false;
};

/// TCLAP takes an empty value (`--voxel ''`) as the option's default, so a
/// mistyped shell variable went unnoticed (found by fuzzing): an empty
/// argument is a usage error, naming the option it was given to.
void refuseEmptyArguments(TCLAP::CmdLine& cmd, int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    if (argv[i][0] != '\0') continue;
    const std::string before = argv[i - 1];
    for (TCLAP::Arg* a : cmd.getArgList()) {
      const std::string flag = a->getFlag().empty() ? "" : "-" + a->getFlag();
      const std::string name = "--" + a->getName();
      if (before == name || (!flag.empty() && before == flag))
        throw UsageError((flag.empty() ? "" : flag + "/") + name + ": an empty value");
    }
    throw UsageError("argument " + std::to_string(i) + " (after the command) is empty");
  }
}
}  // namespace

bool parseArguments(TCLAP::CmdLine& cmd, int argc, char** argv, int& exit_code) {
  // --log-level on every subcommand. TCLAP keeps a pointer to each argument
  // until the command line is gone, so the argument outlives this call.
  static std::vector<std::string> level_names = [] {
    std::vector<std::string> v;
    for (LogLevel l :
         {LogLevel::kError, LogLevel::kWarn, LogLevel::kInfo, LogLevel::kDebug, LogLevel::kTrace})
      v.emplace_back(logLevelName(l));
    return v;
  }();
  static TCLAP::ValuesConstraint<std::string> level_values(level_names);
  static std::vector<std::unique_ptr<TCLAP::ValueArg<std::string>>> level_args;
  level_args.push_back(std::make_unique<TCLAP::ValueArg<std::string>>(
      "", "log-level",
      "diagnostics on stderr: error, warn, info (the default), debug (per keyframe: local "
      "mapping, loop closing, relocalisation; the dynamic filter's stage times) or trace (also "
      "per frame: tracking, matching, the dynamic filter)",
      false, logLevelName(LogLevel::kInfo), &level_values));
  cmd.add(*level_args.back());
  refuseEmptyArguments(cmd, argc, argv);
  ArgumentOutput output;
  cmd.setOutput(&output);
  const bool ok = cmd.parse(argc, argv);
  cmd.setOutput(nullptr);
  if (ok) {
    setLogLevel(*parseLogLevel(level_args.back()->getValue()));  // the constraint admitted it
    return true;
  }
  exit_code = output.failed ? kUsage : kOk;  // error, or --help / --version done
  return false;
}

/// One line for the user: our InputErrors lead with the file name (kept);
/// other library exceptions (MRPT's carry a backtrace) are reduced to the
/// line that says what went wrong.
static std::string userMessage(const std::exception& e) {
  const std::string what = e.what();
  if (dynamic_cast<const InputError*>(&e)) return printableLine(what.substr(0, what.find('\n')));
  return printableLine(oneLineMessage(what));
}

static void printUsage(std::FILE* out) {
  std::fprintf(out,
               "dynslam: RGB-D SLAM that keeps working when people walk through the scene\n\n"
               "usage: dynslam COMMAND [ARGS...]\n"
               "       dynslam COMMAND --help\n\ncommands:\n");
  for (const auto& c : subcommands())
    std::fprintf(out, "  %-10s %s\n", c.name.c_str(), c.summary.c_str());
}

int dispatch(int argc, char** argv) {
  if (argc < 2) {
    printUsage(stderr);
    return kUsage;
  }
  const std::string name = argv[1];
  if (name == "--help" || name == "-h" || name == "help") {
    printUsage(stdout);
    return kOk;
  }
  if (name == "--version") {
    std::printf("dynslam " DYNSLAM_VERSION "\n");
    return kOk;
  }
  for (const auto& c : subcommands()) {
    if (c.name != name) continue;
    std::string prog = "dynslam " + name;
    std::vector<char*> args;
    args.push_back(prog.data());
    for (int i = 2; i < argc; ++i) args.push_back(argv[i]);
    try {
      return c.main(static_cast<int>(args.size()), args.data());
    } catch (const Interrupted& e) {  // its temporaries are gone with the stack
      std::fprintf(stderr, "%s: %s\n", prog.c_str(), e.what());
      return e.exitCode();
    } catch (const UsageError& e) {
      std::fprintf(stderr, "%s: error: %s\nrun '%s --help' for usage\n", prog.c_str(),
                   printableLine(e.what()).c_str(), prog.c_str());
      return kUsage;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "%s: error: %s\n", prog.c_str(), userMessage(e).c_str());
      return kFailure;
    }
  }
  std::fprintf(stderr, "dynslam: unknown command '%s'\n\n", name.c_str());
  printUsage(stderr);
  return kUsage;
}

}  // namespace dynslam::cli
