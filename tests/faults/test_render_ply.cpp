// `dynslam render` on damaged PLY files: each is a one-line error naming the
// file and exit 1, and no PNG is written (PCL used to segfault on a header
// that disagrees with the data, assert on NaN points, and render inf / 1e30
// coordinates as a blank image with exit 0).
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>

#include "fault_support.h"

using namespace dynslam::test;
namespace fs = std::filesystem;

namespace {

/// A binary little-endian PLY: float x y z, uchar red green blue per vertex.
struct PlySpec {
  std::size_t declared = 0;  ///< vertex count in the header
  std::vector<std::array<float, 3>> points;
  std::string element_before, element_after;  ///< extra header lines
  std::string bytes_before, bytes_after;      ///< their data
};

std::vector<std::array<float, 3>> cube(std::size_t n) {
  std::vector<std::array<float, 3>> p;
  for (std::size_t i = 0; i < n; ++i)
    p.push_back({float(i % 10) * 0.1f, float((i / 10) % 10) * 0.1f, float(i / 100) * 0.1f});
  return p;
}

void writePly(const std::string& path, const PlySpec& s) {
  std::ofstream out(path, std::ios::binary);
  out << "ply\nformat binary_little_endian 1.0\n"
      << s.element_before << "element vertex " << s.declared
      << "\nproperty float x\nproperty float y\nproperty float z\n"
         "property uchar red\nproperty uchar green\nproperty uchar blue\n"
      << s.element_after << "end_header\n";
  out << s.bytes_before;
  for (const auto& p : s.points) {
    out.write(reinterpret_cast<const char*>(p.data()), 12);
    const unsigned char rgb[3] = {200, 100, 50};
    out.write(reinterpret_cast<const char*>(rgb), 3);
  }
  out << s.bytes_after;
}

PlySpec valid(std::size_t n = 1000) {
  PlySpec s;
  s.points = cube(n);
  s.declared = n;
  return s;
}

class RenderBadPly : public ::testing::Test {
 protected:
  /// Renders `ply` to out.png; expects the handled fault and no PNG.
  void expectRejected(const PlySpec& spec) {
    const std::string ply = dir / "map.ply";
    writePly(ply, spec);
    const SplitCommandResult r =
        runDynslamSplit({"render", ply, "-o", dir / "out.png", "--width", "64", "--height", "48"});
    expectHandledFault(r, 1, ply);
    EXPECT_EQ(entriesIn(dir.path()), std::vector<std::string>{"map.ply"});
  }
  TempDir dir;
};

}  // namespace

// The control: the test's PLY writer makes files render accepts.
TEST_F(RenderBadPly, ValidPlyRenders) {
  writePly(dir / "map.ply", valid());
  const SplitCommandResult r = runDynslamSplit(
      {"render", dir / "map.ply", "-o", dir / "out.png", "--width", "64", "--height", "48"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::is_regular_file(dir / "out.png"));
}

TEST_F(RenderBadPly, ElementBeforeVertices) {
  PlySpec s = valid();
  s.element_before = "element face 4\nproperty int q\n";
  s.bytes_before = std::string(16, '\0');
  expectRejected(s);
}

TEST_F(RenderBadPly, ElementAfterVertices) {
  PlySpec s = valid();
  s.element_after = "element extra 4\nproperty float q\n";
  s.bytes_after = std::string(16, '\0');
  expectRejected(s);
}

TEST_F(RenderBadPly, MoreVerticesDeclaredThanStored) {
  PlySpec s = valid();
  s.declared = 5000;
  expectRejected(s);
}

TEST_F(RenderBadPly, FewerVerticesDeclaredThanStored) {
  PlySpec s = valid();
  s.declared = 300;
  expectRejected(s);
}

TEST_F(RenderBadPly, AsciiRowsMissing) {
  const std::string ply = dir / "map.ply";
  writeText(ply,
            "ply\nformat ascii 1.0\nelement vertex 10\nproperty float x\nproperty float y\n"
            "property float z\nend_header\n0 0 0\n1 0 0\n0 1 0\n");
  const SplitCommandResult r =
      runDynslamSplit({"render", ply, "-o", dir / "out.png", "--width", "64", "--height", "48"});
  expectHandledFault(r, 1, ply);
  EXPECT_FALSE(fs::exists(dir / "out.png"));
}

TEST_F(RenderBadPly, AFewNanPoints) {
  PlySpec s = valid();
  for (std::size_t i : {3u, 500u, 999u}) s.points[i][1] = std::numeric_limits<float>::quiet_NaN();
  expectRejected(s);
}

TEST_F(RenderBadPly, AllNanPoints) {
  PlySpec s = valid();
  for (auto& p : s.points) p[0] = std::numeric_limits<float>::quiet_NaN();
  expectRejected(s);
}

TEST_F(RenderBadPly, InfiniteCoordinate) {
  PlySpec s = valid();
  s.points[10][2] = std::numeric_limits<float>::infinity();
  expectRejected(s);
}

TEST_F(RenderBadPly, HugeCoordinate) {
  PlySpec s = valid();
  s.points[10][0] = 1e30f;
  expectRejected(s);
}

// The advice lists every format render reads (it left out .bt, found by fuzzing).
TEST_F(RenderBadPly, UnknownExtensionNamesEveryFormat) {
  writeText(dir / "map.xyz", "0 0 0\n");
  const SplitCommandResult r = runDynslamSplit({"render", dir / "map.xyz", "-o", dir / "out.png"});
  expectHandledFault(r, 1, dir / "map.xyz");
  EXPECT_NE(r.err.find(".ply, .glb or .bt"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "out.png"));
}

namespace {
/// PCL's 'camera' element as its writer adds it, with the given viewport
/// and focal length (the other values those of an identity view).
void addCamera(PlySpec& s, int32_t viewport_x, int32_t viewport_y, float focal = 0.f) {
  static const char* const kFloats1[] = {"view_px", "view_py", "view_pz", "x_axisx", "x_axisy",
                                         "x_axisz", "y_axisx", "y_axisy", "y_axisz", "z_axisx",
                                         "z_axisy", "z_axisz", "focal",   "scalex",  "scaley",
                                         "centerx", "centery"};
  s.element_after = "element camera 1\n";
  std::string bytes;
  const auto put = [&](const void* p, std::size_t n) {
    bytes.append(static_cast<const char*>(p), n);
  };
  for (const char* name : kFloats1) {
    s.element_after += std::string("property float ") + name + "\n";
    const std::string n = name;
    const float v = n == "focal" ? focal : (n == "x_axisx" || n == "y_axisy" || n == "z_axisz");
    put(&v, 4);
  }
  s.element_after += "property int viewportx\nproperty int viewporty\n";
  put(&viewport_x, 4);
  put(&viewport_y, 4);
  s.element_after += "property float k1\nproperty float k2\n";
  const float zero = 0;
  put(&zero, 4);
  put(&zero, 4);
  s.bytes_after = bytes;
}
}  // namespace

// The camera element PCL's own writer adds (viewport = the cloud's width x
// height) renders.
TEST_F(RenderBadPly, PclsOwnCameraElementRenders) {
  PlySpec s = valid();
  addCamera(s, 1000, 1);
  writePly(dir / "map.ply", s);
  const SplitCommandResult r = runDynslamSplit(
      {"render", dir / "map.ply", "-o", dir / "out.png", "--width", "64", "--height", "48"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

// PCL sized the cloud from the camera row's viewport and trusted its values:
// large, zero, byte-swapped or NaN values crashed `render` (issue 57).
TEST_F(RenderBadPly, CameraViewportThatDoesNotHoldTheVertices) {
  for (const auto& [x, y] : std::vector<std::pair<int32_t, int32_t>>{
           {0, 0}, {1000000, 1000000}, {-1000, -1}, {int32_t(0xE8030000), 1}, {999, 1}}) {
    PlySpec s = valid();
    addCamera(s, x, y);
    expectRejected(s);
  }
}

TEST_F(RenderBadPly, CameraValueThatIsNotFinite) {
  PlySpec s = valid();
  addCamera(s, 1000, 1, std::numeric_limits<float>::quiet_NaN());
  expectRejected(s);
}

// No vertices, then a camera element: PCL crashed; now the map is empty and
// render says so.
TEST_F(RenderBadPly, NoVerticesThenACameraElement) {
  PlySpec s = valid(0);
  addCamera(s, 0, 1);
  expectRejected(s);
}
