#pragma once
// Where dynslam finds its read-only data: the camera and SLAM configs and the
// ORB vocabulary (configs/), and the detector model. The same binary runs from
// the build tree (the source tree's configs/, ../shared/models) and installed
// by `cmake --install` (PREFIX/bin/dynslam beside PREFIX/share/dynslam), from
// any working folder; environment variables override both.
#include <string>

namespace dynslam {

/// Folder holding configs/: $DYNSLAM_DATA_DIR if set; else the installed
/// share/dynslam found relative to the executable (bin/../share/dynslam)
/// when it holds configs/; else the source tree (build-tree binary).
/// Throws InputError naming the folder when $DYNSLAM_DATA_DIR has no configs/.
std::string dataDir();

/// True when the executable sits in an install tree (bin/../share/dynslam
/// holds configs/), whatever the environment says.
bool runningInstalled();

/// configs/ folder: $DYNSLAM_CONFIG_DIR if set, else dataDir()/configs.
std::string configDir();

/// $DYNSLAM_SHARED_DIR if set, else <source>/../shared (the build tree's test
/// and benchmark data; the installed tool does not assume it).
std::string sharedDataDir();

/// A model file (e.g. "yolov5n_480x640.onnx") in the first models folder of:
/// $DYNSLAM_MODELS_DIR (only there when set); else, installed,
/// $DYNSLAM_SHARED_DIR/models (if set) and dataDir()/models; else (build tree)
/// sharedDataDir()/models.
/// Throws InputError(file) listing every folder it looked in.
std::string findModelFile(const std::string& file);

}  // namespace dynslam
