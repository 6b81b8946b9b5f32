// Bad rawlog inputs of issue 20 through the real binary: a rawlog of several
// 3D sensors without --sensor, an unknown label, --sensor on a TUM folder
// (bad arguments, exit 2); a depth camera that cannot be registered, a range
// image of another size than its camera, a models folder without the model
// (bad files, exit 1). Each names what to fix in one line.
#include <filesystem>

#include "fault_support.h"
#include "testing/mrpt_rawlog_writer.h"

using namespace dynslam::test;
namespace fs = std::filesystem;

namespace {

mrpt::img::TCamera camera64(double fx) {
  mrpt::img::TCamera c;
  c.ncols = 64;
  c.nrows = 48;
  c.setIntrinsicParamsFromValues(fx, fx, 31.5, 23.5);
  return c;
}

/// One scan per label; `depth_camera` for every scan, RGB camera 64x48.
std::string writeRawlog(const TempDir& d, const std::vector<std::string>& labels,
                        const mrpt::img::TCamera& depth_camera, cv::Size depth_size = {64, 48},
                        const mrpt::poses::CPose3D& rgb_wrt_depth = mrptAxesChange()) {
  const std::string path = d / "rec.rawlog";
  MrptRawlogWriter w(path);
  for (const std::string& label : labels) {
    ScanSpec s;
    s.label = label;
    s.timestamp = 10.0;
    s.rgb_name = w.writeImage(cv::Mat(48, 64, CV_8UC3, cv::Scalar(9, 9, 9)), label + ".png");
    s.depth = cv::Mat(depth_size, CV_16UC1, cv::Scalar(5000));
    s.depth_camera = depth_camera;
    s.rgb_camera = camera64(50);
    s.rgb_wrt_depth = rgb_wrt_depth;
    w.scan(s);
  }
  return path;
}

mrpt::poses::CPose3D offset() {
  return mrptAxesChange() + mrpt::poses::CPose3D(0.025, 0, 0, 0, 0, 0);
}

}  // namespace

TEST(RawlogInputs, SeveralSensorsWithoutSensorIsExit2ListingThem) {
  TempDir d;
  const std::string rawlog = writeRawlog(d, {"KINECT", "XTION"}, camera64(50));
  const SplitCommandResult r = runDynslamSplit({"run", rawlog, "-o", d / "out", "--mode", "off"});
  expectHandledFault(r, 2, rawlog);
  EXPECT_NE(r.err.find("--sensor LABEL: 'KINECT' (1 scans), 'XTION' (1 scans)"), std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(d / "out"));
}

TEST(RawlogInputs, UnknownSensorIsExit2) {
  TempDir d;
  const std::string rawlog = writeRawlog(d, {"KINECT"}, camera64(50));
  const SplitCommandResult r =
      runDynslamSplit({"run", rawlog, "-o", d / "out", "--mode", "off", "--sensor", "XTION"});
  expectHandledFault(r, 2, rawlog);
  EXPECT_NE(r.err.find("--sensor XTION"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("'KINECT' (1 scans)"), std::string::npos) << r.err;
}

TEST(RawlogInputs, SensorOnATumFolderIsExit2) {
  TempDir d;
  const MiniTum tum = makeMiniTum(d.path(), 2);
  const SplitCommandResult r =
      runDynslamSplit({"run", tum.dir, "-o", d / "out", "--mode", "off", "--sensor", "KINECT"});
  expectHandledFault(r, 2, tum.dir);
}

TEST(RawlogInputs, DepthCameraWithoutIntrinsicsIsExit1) {
  TempDir d;
  const std::string rawlog = writeRawlog(d, {"KINECT"}, camera64(0), {64, 48}, offset());
  const SplitCommandResult r = runDynslamSplit({"run", rawlog, "-o", d / "out", "--mode", "off"});
  expectHandledFault(r, 1, rawlog);
  EXPECT_NE(r.err.find("cameraParams"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(d / "out"));
}

TEST(RawlogInputs, RangeImageOfAnotherSizeThanItsCameraIsExit1) {
  TempDir d;
  const std::string rawlog = writeRawlog(d, {"KINECT"}, camera64(55), {32, 24}, offset());
  const SplitCommandResult r = runDynslamSplit({"run", rawlog, "-o", d / "out", "--mode", "off"});
  expectHandledFault(r, 1, "KINECT_depth_0.bin");
  EXPECT_NE(r.err.find("range image is 32x24"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(d / "out/trajectory.txt"));
}

TEST(RawlogInputs, ModelsDirWithoutTheModelIsExit1NamingIt) {
  TempDir d;
  const MiniTum tum = makeMiniTum(d.path(), 2);
  const SplitCommandResult r = runShellSplit("env " + shellQuote("DYNSLAM_MODELS_DIR=" + d.path()) +
                                             " " + shellQuote(dynslamBinary()) + " run " +
                                             shellQuote(tum.dir) + " -o " + shellQuote(d / "out"));
  expectHandledFault(r, 1, "yolov5n_480x640.onnx");
  EXPECT_NE(r.err.find("looked in " + d.path() + ")"), std::string::npos) << r.err;
}
