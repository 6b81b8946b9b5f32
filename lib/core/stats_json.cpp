#include "core/stats_json.h"

namespace dynslam {

void writeSummaryStatsJson(JsonWriter& w, const std::string& key, const SummaryStats& s,
                           const std::string& count_key, std::size_t count) {
  w.beginObject(key)
      .value(count_key, count)
      .value("mean", s.mean)
      .value("median", s.median)
      .value("p95", s.p95)
      .value("max", s.max)
      .endObject();
}

}  // namespace dynslam
