#include "occupancy/map_server_io.h"

#include <opencv2/imgcodecs.hpp>

#include <cstdio>
#include <filesystem>
#include <sstream>
#include <stdexcept>

#include "core/atomic_file.h"
#include "core/yaml_writer.h"

namespace dynslam {

namespace fs = std::filesystem;

std::string mapServerImagePath(const std::string& yaml_path) {
  return fs::path(yaml_path).replace_extension(".pgm").string();
}

namespace {

cv::Mat gridImage(const OccupancyGrid2D& grid) {
  cv::Mat img(grid.height, grid.width, CV_8UC1);
  for (int iy = 0; iy < grid.height; ++iy) {
    auto* row = img.ptr<std::uint8_t>(grid.height - 1 - iy);  // image top = highest y
    for (int ix = 0; ix < grid.width; ++ix) {
      const std::int8_t c = grid.at(ix, iy);
      row[ix] = c == OccupancyGrid2D::kOccupied ? 0 : c == OccupancyGrid2D::kFree ? 254 : 205;
    }
  }
  return img;
}

std::string yamlText(const std::string& image_name, const OccupancyGrid2D& grid,
                     const LevelFrame& frame) {
  std::ostringstream y;
  char buf[256];
  y << "# 2D occupancy grid of the static scene (dynslam export), ROS map_server format.\n"
       "# Grid frame = level frame: z is up, p_level = R * p_world (SLAM world frame);\n";
  for (int r = 0; r < 3; ++r) {
    std::snprintf(buf, sizeof buf, "#   R row %d: %.6f %.6f %.6f\n", r, frame.R(r, 0),
                  frame.R(r, 1), frame.R(r, 2));
    y << buf;
  }
  std::snprintf(buf, sizeof buf, "# floor at level z = %.4f m (%s)\n", frame.floor_height,
                frame.floor_source.c_str());
  y << buf;
  y << "image: " << yamlQuote(image_name) << "\n";  // a file name may hold any character
  std::snprintf(buf, sizeof buf, "resolution: %.6f\norigin: [%.6f, %.6f, 0.0]\n", grid.resolution,
                grid.origin_x, grid.origin_y);
  y << buf << "negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n";
  return y.str();
}

}  // namespace

void writeMapServerFiles(const std::string& yaml_path, const OccupancyGrid2D& grid,
                         const LevelFrame& frame) {
  const std::string image_path = mapServerImagePath(yaml_path);
  std::vector<std::uint8_t> pgm;
  if (!cv::imencode(".pgm", gridImage(grid), pgm)) {
    throw std::runtime_error(image_path + ": cannot encode the grid image");
  }
  const std::string text = yamlText(fs::path(image_path).filename().string(), grid, frame);
  writeFileAtomically(
      image_path,
      [&](std::ostream& out) {
        out.write(reinterpret_cast<const char*>(pgm.data()), std::streamsize(pgm.size()));
      },
      /*binary=*/true);
  try {
    writeFileAtomically(yaml_path, [&](std::ostream& out) { out << text; });
  } catch (...) {
    std::error_code ec;
    fs::remove(image_path, ec);
    throw;
  }
}

}  // namespace dynslam
