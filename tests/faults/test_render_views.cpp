// `dynslam render` with views that show nothing of the map: an orbit angle
// out of range, a camera thousands of km away or looking away, keyframes
// far beyond any map point, a map too large to be drawn, an OctoMap whose
// resolution is 1e-30 or 1e30 m. Each wrote a one-colour PNG with exit 0, or
// printed an MRPT assertion (issue 57); now one line naming the option
// (exit 2) or the file (exit 1), and no PNG.
#include <octomap/OcTree.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "fault_support.h"

using namespace dynslam::test;
namespace fs = std::filesystem;

namespace {

/// An ASCII PLY of `points`.
void writeAsciiPly(const std::string& path, const std::vector<std::array<double, 3>>& points) {
  std::ofstream out(path);
  out << "ply\nformat ascii 1.0\nelement vertex " << points.size()
      << "\nproperty float x\nproperty float y\nproperty float z\n"
         "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n";
  for (const auto& p : points) out << p[0] << ' ' << p[1] << ' ' << p[2] << " 200 100 50\n";
}

/// 1000 points filling the unit cube at the origin, 0.1 m apart.
std::vector<std::array<double, 3>> unitCube() {
  std::vector<std::array<double, 3>> p;
  for (int i = 0; i < 1000; ++i)
    p.push_back({(i % 10) * 0.1, (i / 10 % 10) * 0.1, (i / 100) * 0.1});
  return p;
}

class RenderViews : public ::testing::Test {
 protected:
  void SetUp() override { writeAsciiPly(ply_, unitCube()); }
  SplitCommandResult render(const std::string& map, std::vector<std::string> extra) {
    std::vector<std::string> args = {"render",  map,  "-o",       dir_ / "out.png",
                                     "--width", "64", "--height", "48"};
    args.insert(args.end(), extra.begin(), extra.end());
    return runDynslamSplit(args);
  }
  void expectRefused(const std::string& map, std::vector<std::string> extra, int code,
                     const std::string& named) {
    SCOPED_TRACE(extra.empty() ? map : extra.back());
    expectHandledFault(render(map, extra), code, named);
    EXPECT_FALSE(fs::exists(dir_ / "out.png"));
  }
  TempDir dir_;
  const std::string ply_ = dir_ / "cube.ply";
};

}  // namespace

// The controls: every named view and a pose that looks at the cube render.
TEST_F(RenderViews, ViewsOfTheMapRender) {
  for (const char* view : {"top", "front", "orbit-90", "orbit--360", "pose:0.5,0.5,-3,0,0,0,1"}) {
    const SplitCommandResult r = render(ply_, {"--view", view});
    EXPECT_EQ(r.exit_code, 0) << view << ": " << r.err;
    EXPECT_TRUE(fs::is_regular_file(dir_ / "out.png")) << view;
    fs::remove(dir_ / "out.png");
  }
}

TEST_F(RenderViews, OrbitAnglesBeyondAFullTurnAreUsageErrors) {
  expectRefused(ply_, {"--view", "orbit-400"}, 2, "orbit-400");
  expectRefused(ply_, {"--view", "orbit--1e300"}, 2, "orbit--1e300");
}

TEST_F(RenderViews, ACameraThousandsOfKilometresAwayIsAUsageError) {
  expectRefused(ply_, {"--view", "pose:5e6,0.5,0.5,0,0,0,1"}, 2, "5e6");
}

// Within the bound of map points but showing none of them: behind the
// camera, or 50 km down its axis (beyond what OpenGL draws).
TEST_F(RenderViews, APoseThatShowsNoPointIsAUsageError) {
  expectRefused(ply_, {"--view", "pose:0.5,0.5,3,0,0,0,1"}, 2, "--view");
  expectRefused(ply_, {"--view", "pose:0.5,0.5,-50000,0,0,0,1"}, 2, "--view");
}

// A keyframe 500 km away (the trajectory reader takes up to 1000 km) made
// the named views frame it with the map: a dot, or nothing.
TEST_F(RenderViews, AKeyframeFarBeyondTheMapNamesTheTrajectory) {
  const std::string traj = dir_ / "keyframes.txt";
  writeText(traj, "1.0 0 0 0 0 0 0 1\n2.0 500000 0 0 0 0 0 1\n");
  expectRefused(ply_, {"--trajectory", traj}, 1, traj);
}

// Half the points at the origin, half 90 km away (both within the points'
// bound): no named view can hold them.
TEST_F(RenderViews, AMapTooLargeToDrawNamesTheMap) {
  auto points = unitCube();
  for (auto p : unitCube()) points.push_back({p[0] + 90000, p[1], p[2]});
  const std::string wide = dir_ / "wide.ply";
  writeAsciiPly(wide, points);
  expectRefused(wide, {}, 1, wide);
}

// An OctoMap whose header says 1e-30 or 1e30 m per leaf (MRPT asserted, or
// a one-colour picture): the file and the header's line (4, below) named.
TEST_F(RenderViews, AnOctoMapResolutionOutsideTheConfigsRangeNamesItsLine) {
  octomap::OcTree tree(0.05);
  for (const auto& p : unitCube()) tree.updateNode(octomap::point3d(p[0], p[1], p[2]), true);
  std::ostringstream bytes;
  ASSERT_TRUE(tree.writeBinaryConst(bytes));
  const std::string whole = bytes.str();
  const std::string data = whole.substr(whole.find("data\n") + 5);
  const std::string size = "size " + std::to_string(tree.size()) + "\n";
  const std::string good = dir_ / "good.bt";
  writeText(good, "# Octomap OcTree binary file\nid OcTree\n" + size + "res 0.05\ndata\n" + data);
  const SplitCommandResult r = render(good, {});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  fs::remove(dir_ / "out.png");
  for (const char* res : {"1e-30", "1e30", "0.001"}) {
    const std::string bt = dir_ / "bad.bt";
    writeText(
        bt, "# Octomap OcTree binary file\nid OcTree\n" + size + "res " + res + "\ndata\n" + data);
    expectRefused(bt, {}, 1, bt + ":4: ");
  }
}
