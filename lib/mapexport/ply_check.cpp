#include "mapexport/ply_check.h"

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <vector>

#include "core/errors.h"

namespace dynslam {
namespace {

struct PlyElement {
  std::string name;
  std::size_t count = 0;
  std::size_t row_bytes = 0;  ///< binary size of one row (scalar properties)
  std::vector<std::string> properties;
  std::vector<std::string> types;  ///< of the scalar properties, in order
  bool has_list = false;
  std::size_t line = 0;
};

/// Size in bytes of a PLY scalar type; 0 for an unknown name.
std::size_t scalarBytes(const std::string& type) {
  if (type == "char" || type == "uchar" || type == "int8" || type == "uint8") return 1;
  if (type == "short" || type == "ushort" || type == "int16" || type == "uint16") return 2;
  if (type == "int" || type == "uint" || type == "float" || type == "int32" || type == "uint32" ||
      type == "float32")
    return 4;
  if (type == "double" || type == "float64") return 8;
  return 0;
}

/// Strict element count: digits only, at most a billion rows.
bool parseCount(const std::string& text, std::size_t& count) {
  if (text.empty() || text.size() > 10 || text.find_first_not_of("0123456789") != std::string::npos)
    return false;
  count = std::stoull(text);
  return count <= 1000000000ull;
}

std::vector<std::string> words(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> out;
  for (std::string w; in >> w;) out.push_back(w);
  return out;
}

/// Reads the header lines up to end_header; leaves `in` at the first data byte.
/// `header_lines` receives the number of header lines (for data line numbers).
std::vector<PlyElement> readHeader(const std::string& path, std::istream& in, bool& ascii,
                                   bool& big_endian, std::size_t& header_lines) {
  std::string line;
  std::size_t line_no = 0;
  auto next = [&]() -> bool {
    if (!std::getline(in, line)) return false;
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    return true;
  };
  if (!next() || line != "ply") throw InputError(path, "not a PLY file (no 'ply' first line)");
  std::vector<PlyElement> elements;
  bool have_format = false;
  for (;;) {
    if (!next()) throw InputError(path, "PLY header has no end_header line");
    const std::vector<std::string> w = words(line);
    if (w.empty() || w[0] == "comment" || w[0] == "obj_info") continue;
    if (w[0] == "end_header") break;
    if (w[0] == "format") {
      if (w.size() != 3 ||
          (w[1] != "ascii" && w[1] != "binary_little_endian" && w[1] != "binary_big_endian"))
        throw InputError(path, line_no, "unknown PLY format line '" + line + "'");
      ascii = w[1] == "ascii";
      big_endian = w[1] == "binary_big_endian";
      have_format = true;
    } else if (w[0] == "element") {
      PlyElement e;
      if (w.size() != 3 || !parseCount(w[2], e.count))
        throw InputError(path, line_no, "bad element line '" + line + "'");
      e.name = w[1];
      e.line = line_no;
      elements.push_back(e);
    } else if (w[0] == "property") {
      if (elements.empty()) throw InputError(path, line_no, "property before any element");
      if (w.size() == 5 && w[1] == "list") {  // sized per row: only in empty elements
        elements.back().has_list = true;
        elements.back().properties.push_back(w[4]);
        continue;
      }
      const std::size_t bytes = w.size() == 3 ? scalarBytes(w[1]) : 0;
      if (bytes == 0) throw InputError(path, line_no, "bad property line '" + line + "'");
      elements.back().row_bytes += bytes;
      elements.back().properties.push_back(w[2]);
      elements.back().types.push_back(w[1]);
    } else {
      throw InputError(path, line_no, "unexpected PLY header line '" + line + "'");
    }
  }
  if (!have_format) throw InputError(path, "PLY header has no format line");
  header_lines = line_no;
  return elements;
}

bool hasProperty(const PlyElement& e, const char* name) {
  for (const auto& p : e.properties)
    if (p == name) return true;
  return false;
}

/// One 'vertex' element with x, y, z first; after it only PCL's 'camera' row
/// and empty elements (PCL's writer adds "element face 0").
void checkElements(const std::string& path, const std::vector<PlyElement>& elements) {
  if (elements.empty()) throw InputError(path, "PLY header declares no elements");
  const PlyElement& v = elements.front();
  if (v.name != "vertex")
    throw InputError(path, v.line,
                     "element '" + v.name + "' before the vertices: point clouds only");
  if (!hasProperty(v, "x") || !hasProperty(v, "y") || !hasProperty(v, "z"))
    throw InputError(path, v.line, "vertex element lacks x, y or z");
  if (v.has_list) throw InputError(path, v.line, "list property in the vertex element");
  for (std::size_t i = 1; i < elements.size(); ++i) {
    const PlyElement& e = elements[i];
    if (e.count == 0) continue;
    if (e.name != "camera" || e.count > 1 || e.has_list)
      throw InputError(path, e.line,
                       "element '" + e.name + "' after the vertices: point clouds only");
  }
}

void checkBinarySize(const std::string& path, std::istream& in,
                     const std::vector<PlyElement>& elements) {
  std::size_t expected = 0;
  for (const auto& e : elements) expected += e.count * e.row_bytes;
  const auto data_start = in.tellg();
  in.seekg(0, std::ios::end);
  const auto size = static_cast<std::size_t>(in.tellg() - data_start);
  const std::size_t nv = elements.front().count;
  if (size < expected)
    throw InputError(path, "data ends after " + std::to_string(size) + " of the " +
                               std::to_string(expected) + " bytes the header declares (" +
                               std::to_string(nv) + " vertices): truncated or wrong count");
  if (size > expected)
    throw InputError(path, std::to_string(size - expected) +
                               " bytes after the data the header declares (" + std::to_string(nv) +
                               " vertices): wrong vertex count");
}

/// `camera_row` receives the words of the one-row 'camera' element, if any.
void checkAsciiRows(const std::string& path, std::istream& in,
                    const std::vector<PlyElement>& elements, std::size_t header_lines,
                    std::vector<std::string>& camera_row) {
  std::string line;
  std::size_t line_no = header_lines, row = 0, element = 0;
  while (std::getline(in, line)) {
    ++line_no;
    const std::vector<std::string> w = words(line);
    if (w.empty()) continue;
    while (element < elements.size() && row == elements[element].count) {
      ++element;
      row = 0;
    }
    if (element == elements.size())
      throw InputError(path, line_no, "more data rows than the header declares");
    if (w.size() != elements[element].properties.size())
      throw InputError(path, line_no,
                       std::to_string(w.size()) + " values, the header declares " +
                           std::to_string(elements[element].properties.size()));
    if (elements[element].name == "camera") camera_row = w;
    ++row;
  }
  std::size_t rows = 0, expected = 0;
  for (std::size_t i = 0; i < elements.size(); ++i) {
    expected += elements[i].count;
    if (i < element) rows += elements[i].count;
  }
  rows += row;
  if (rows != expected)
    throw InputError(path, "data ends after " + std::to_string(rows) + " of the " +
                               std::to_string(expected) + " rows the header declares");
}

/// One binary scalar of `type` at `p` as a double.
double binaryValue(const std::string& type, const unsigned char* p, bool big_endian) {
  unsigned char b[8];
  const std::size_t n = scalarBytes(type);
  for (std::size_t i = 0; i < n; ++i) b[i] = big_endian ? p[n - 1 - i] : p[i];  // to little
  const auto as = [&](auto v) {
    std::memcpy(&v, b, sizeof v);
    return double(v);
  };
  if (type == "char" || type == "int8") return as(int8_t{});
  if (type == "uchar" || type == "uint8") return as(uint8_t{});
  if (type == "short" || type == "int16") return as(int16_t{});
  if (type == "ushort" || type == "uint16") return as(uint16_t{});
  if (type == "int" || type == "int32") return as(int32_t{});
  if (type == "uint" || type == "uint32") return as(uint32_t{});
  if (type == "float" || type == "float32") return as(float{});
  return as(double{});
}

/// PCL's one-row 'camera' element (checkElements allows it after the
/// vertices), or null.
const PlyElement* cameraElement(const std::vector<PlyElement>& elements) {
  for (const PlyElement& e : elements)
    if (e.name == "camera" && e.count == 1) return &e;
  return nullptr;
}

/// The row of `camera` (one of `elements`) as numbers.
std::vector<double> binaryCameraRow(std::istream& in, std::streampos data_start,
                                    const std::vector<PlyElement>& elements,
                                    const PlyElement& camera, bool big_endian) {
  std::size_t offset = 0;
  for (const PlyElement* e = elements.data(); e != &camera; ++e) offset += e->count * e->row_bytes;
  std::vector<unsigned char> row(camera.row_bytes);
  in.clear();
  in.seekg(data_start + std::streamoff(offset));
  in.read(reinterpret_cast<char*>(row.data()), std::streamsize(row.size()));
  std::vector<double> values;
  std::size_t at = 0;
  for (const std::string& type : camera.types) {
    values.push_back(binaryValue(type, row.data() + at, big_endian));
    at += scalarBytes(type);
  }
  return values;
}

/// PCL sizes the cloud it reads from the camera row's viewport (width x
/// height) and trusts its other values: a viewport that is not the vertex
/// count, or a value that is not finite, crashed `render` (issue 57). PCL's
/// own writer stores the cloud's width and height there.
void checkCameraRow(const std::string& path, const PlyElement& camera,
                    const std::vector<double>& values, std::size_t vertices) {
  double width = 1, height = 1;
  for (std::size_t i = 0; i < values.size() && i < camera.properties.size(); ++i) {
    if (!std::isfinite(values[i]))
      throw InputError(path, camera.line,
                       "camera element: '" + camera.properties[i] + "' is not a finite number");
    if (camera.properties[i] == "viewportx") width = values[i];
    if (camera.properties[i] == "viewporty") height = values[i];
  }
  if (!(width >= 0 && height >= 0 && width * height == double(vertices)))
    throw InputError(path, camera.line,
                     "camera element: viewport " + std::to_string(long(width)) + " x " +
                         std::to_string(long(height)) + " does not hold the " +
                         std::to_string(vertices) + " vertices");
}

}  // namespace

PlyLayout checkPlyFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot open");
  PlyLayout layout;
  std::size_t header_lines = 0;
  bool big_endian = false;
  const std::vector<PlyElement> elements =
      readHeader(path, in, layout.ascii, big_endian, header_lines);
  checkElements(path, elements);
  layout.vertices = elements.front().count;
  const PlyElement* camera = cameraElement(elements);
  std::vector<double> camera_row;
  if (layout.ascii) {
    std::vector<std::string> row;
    checkAsciiRows(path, in, elements, header_lines, row);
    for (const std::string& w : row) {
      char* end = nullptr;
      const double v = std::strtod(w.c_str(), &end);
      camera_row.push_back(end && *end == '\0' ? v : std::nan(""));
    }
  } else {
    const std::streampos data_start = in.tellg();
    checkBinarySize(path, in, elements);
    if (camera) camera_row = binaryCameraRow(in, data_start, elements, *camera, big_endian);
  }
  if (camera) checkCameraRow(path, *camera, camera_row, layout.vertices);
  return layout;
}

}  // namespace dynslam
