#pragma once
// A SummaryStats as a JSON object: run reports and benchmark reports print
// the same members (mean, median, p95, max) under one spelling, so that
// scripts reading either report find them alike.
#include <cstddef>
#include <string>

#include "core/json_writer.h"
#include "core/stats.h"

namespace dynslam {

/// Member `key`: {"<count_key>": count, "mean", "median", "p95", "max"}.
void writeSummaryStatsJson(JsonWriter& w, const std::string& key, const SummaryStats& s,
                           const std::string& count_key, std::size_t count);

}  // namespace dynslam
