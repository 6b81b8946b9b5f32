#pragma once
// Minimal streaming JSON emitter for run reports and benchmark results.
// Reports are written once at the end of a run; a streaming writer keeps the
// report code declarative (key, value, ...) without a DOM library.
#include <cstdint>
#include <string>
#include <vector>

namespace dynslam {

class JsonWriter {
 public:
  JsonWriter& beginObject(const std::string& key = "");
  JsonWriter& endObject();
  JsonWriter& beginArray(const std::string& key = "");
  JsonWriter& endArray();

  JsonWriter& value(const std::string& key, double v);
  JsonWriter& value(const std::string& key, int64_t v);
  JsonWriter& value(const std::string& key, int v) { return value(key, int64_t(v)); }
  JsonWriter& value(const std::string& key, std::size_t v) { return value(key, int64_t(v)); }
  JsonWriter& value(const std::string& key, bool v);
  JsonWriter& value(const std::string& key, const std::string& v);
  JsonWriter& value(const std::string& key, const char* v) { return value(key, std::string(v)); }
  /// Array element forms (inside beginArray()).
  JsonWriter& element(double v) { return value("", v); }
  JsonWriter& element(const std::string& v) { return value("", v); }

  /// The document; all objects/arrays must be closed.
  std::string str() const;

  /// `s` as a quoted JSON string, every control character (and DEL) escaped;
  /// also a YAML double-quoted scalar (yamlQuote).
  static std::string escape(const std::string& s);

 private:
  void prefix(const std::string& key);
  std::string out_;
  std::vector<bool> first_;  // per open scope: no element written yet
  std::vector<bool> is_array_;
};

}  // namespace dynslam
