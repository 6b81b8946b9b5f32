#include "core/log.h"

#include <array>
#include <atomic>
#include <cstdarg>
#include <cstdio>
#include <mutex>
#include <vector>

namespace dynslam {

namespace {

std::atomic<int> g_level{static_cast<int>(LogLevel::kInfo)};
std::mutex g_sink_mutex;
LogSink g_sink;

constexpr std::array<LogLevel, 5> kLevels = {LogLevel::kError, LogLevel::kWarn, LogLevel::kInfo,
                                             LogLevel::kDebug, LogLevel::kTrace};

}  // namespace

void setLogLevel(LogLevel level) {
  g_level.store(static_cast<int>(level), std::memory_order_relaxed);
}

LogLevel logLevel() { return static_cast<LogLevel>(g_level.load(std::memory_order_relaxed)); }

bool logEnabled(LogLevel level) {
  return static_cast<int>(level) <= g_level.load(std::memory_order_relaxed);
}

const char* logLevelName(LogLevel level) {
  switch (level) {
    case LogLevel::kError:
      return "error";
    case LogLevel::kWarn:
      return "warn";
    case LogLevel::kInfo:
      return "info";
    case LogLevel::kDebug:
      return "debug";
    case LogLevel::kTrace:
      return "trace";
  }
  return "?";
}

std::optional<LogLevel> parseLogLevel(const std::string& name) {
  for (LogLevel l : kLevels)
    if (name == logLevelName(l)) return l;
  return std::nullopt;
}

void logf(LogLevel level, const char* channel, const char* format, ...) {
  if (!logEnabled(level)) return;
  std::va_list args;
  va_start(args, format);
  std::va_list again;
  va_copy(again, args);
  const int n = std::vsnprintf(nullptr, 0, format, args);
  va_end(args);
  std::string line = "[" + std::string(channel) + "] ";
  const std::size_t head = line.size();
  if (n > 0) {
    line.resize(head + static_cast<std::size_t>(n) + 1);
    std::vsnprintf(&line[head], static_cast<std::size_t>(n) + 1, format, again);
    line.resize(head + static_cast<std::size_t>(n));
  }
  va_end(again);
  line += '\n';
  std::lock_guard<std::mutex> lock(g_sink_mutex);
  if (g_sink) {
    g_sink(line);
  } else {
    std::fwrite(line.data(), 1, line.size(), stderr);
  }
}

void setLogSink(LogSink sink) {
  std::lock_guard<std::mutex> lock(g_sink_mutex);
  g_sink = std::move(sink);
}

}  // namespace dynslam
