#pragma once
// One switch for diagnostic output: every stage logs through here with a
// level and a channel ("track", "map", "loop", ...), and `--log-level` (all
// subcommands) decides what is printed. It replaces one environment switch
// per stage, each with its own fprintf, which a user had to know by name.
//
// Levels: error < warn < info < debug (per keyframe / per loop candidate and
// summaries) < trace (per frame, per matching pass). The default is info.
// Lines go to stderr as "[channel] message", one write per line, so threads
// do not interleave within a line.
#include <functional>
#include <optional>
#include <string>

namespace dynslam {

enum class LogLevel { kError = 0, kWarn, kInfo, kDebug, kTrace };

void setLogLevel(LogLevel level);
LogLevel logLevel();
/// True when messages of `level` are printed (test it before costly arguments).
bool logEnabled(LogLevel level);

/// "error", "warn", "info", "debug", "trace".
const char* logLevelName(LogLevel level);
/// The level of a name above; nullopt for any other text.
std::optional<LogLevel> parseLogLevel(const std::string& name);

/// printf-style message; prints "[channel] message\n" when `level` is enabled.
void logf(LogLevel level, const char* channel, const char* format, ...)
    __attribute__((format(printf, 3, 4)));

/// Where lines go (each with its trailing newline); empty: stderr. For tests.
using LogSink = std::function<void(const std::string& line)>;
void setLogSink(LogSink sink);

}  // namespace dynslam
