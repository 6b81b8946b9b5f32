#include "core/json_writer.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace dynslam {

std::string JsonWriter::escape(const std::string& s) {
  std::string o = "\"";
  for (unsigned char c : s) {
    switch (c) {
      case '"':
        o += "\\\"";
        break;
      case '\\':
        o += "\\\\";
        break;
      case '\n':
        o += "\\n";
        break;
      case '\t':
        o += "\\t";
        break;
      case '\r':
        o += "\\r";
        break;
      default:
        if (c < 0x20 || c == 0x7F) {  // DEL: not printable in YAML, which shares this
          char b[8];
          std::snprintf(b, sizeof b, "\\u%04x", c);
          o += b;
        } else {
          o += static_cast<char>(c);
        }
    }
  }
  return o + "\"";
}

void JsonWriter::prefix(const std::string& key) {
  if (!first_.empty()) {
    if (!first_.back()) out_ += ",";
    first_.back() = false;
    out_ += "\n" + std::string(2 * first_.size(), ' ');
    if (!is_array_.back()) {
      if (key.empty()) throw std::logic_error("JsonWriter: object member needs a key");
      out_ += escape(key) + ": ";
    }
  }
}

JsonWriter& JsonWriter::beginObject(const std::string& key) {
  prefix(key);
  out_ += "{";
  first_.push_back(true);
  is_array_.push_back(false);
  return *this;
}

JsonWriter& JsonWriter::beginArray(const std::string& key) {
  prefix(key);
  out_ += "[";
  first_.push_back(true);
  is_array_.push_back(true);
  return *this;
}

JsonWriter& JsonWriter::endObject() {
  if (first_.empty() || is_array_.back()) throw std::logic_error("JsonWriter: unbalanced }");
  const bool empty = first_.back();
  first_.pop_back();
  is_array_.pop_back();
  if (!empty) out_ += "\n" + std::string(2 * first_.size(), ' ');
  out_ += "}";
  return *this;
}

JsonWriter& JsonWriter::endArray() {
  if (first_.empty() || !is_array_.back()) throw std::logic_error("JsonWriter: unbalanced ]");
  const bool empty = first_.back();
  first_.pop_back();
  is_array_.pop_back();
  if (!empty) out_ += "\n" + std::string(2 * first_.size(), ' ');
  out_ += "]";
  return *this;
}

JsonWriter& JsonWriter::value(const std::string& key, double v) {
  prefix(key);
  if (!std::isfinite(v)) {
    out_ += "null";  // JSON has no NaN/Inf
  } else {
    char b[32];
    std::snprintf(b, sizeof b, "%.10g", v);
    out_ += b;
  }
  return *this;
}

JsonWriter& JsonWriter::value(const std::string& key, int64_t v) {
  prefix(key);
  out_ += std::to_string(v);
  return *this;
}

JsonWriter& JsonWriter::value(const std::string& key, bool v) {
  prefix(key);
  out_ += v ? "true" : "false";
  return *this;
}

JsonWriter& JsonWriter::value(const std::string& key, const std::string& v) {
  prefix(key);
  out_ += escape(v);
  return *this;
}

std::string JsonWriter::str() const {
  if (!first_.empty()) throw std::logic_error("JsonWriter: unclosed scope");
  return out_ + "\n";
}

}  // namespace dynslam
