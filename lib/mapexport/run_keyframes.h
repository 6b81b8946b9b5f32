#pragma once
// The keyframes of a finished run as the exporters fuse them: each keyframe
// pose matched to its frame of the input sequence, with the dynamic mask to
// leave out and, on composite sequences, the ground-truth people mask. The
// dense cloud (run_directory.h) and the occupancy maps (lib/occupancy) both
// walk a run this way, so they read the same pixels under the same poses.
#include <opencv2/core.hpp>

#include <functional>
#include <string>

#include "core/rgbd_frame.h"
#include "core/trajectory.h"
#include "mapexport/run_directory.h"

namespace dynslam {

/// One keyframe, ready to fuse.
struct RunKeyframe {
  const StampedPose* keyframe = nullptr;  ///< the pose to fuse with (camera-to-world)
  RGBDFrame frame;
  cv::Mat dynamic_mask;  ///< empty or CV_8UC1 of the image size, non-zero = dynamic
  cv::Mat truth;         ///< empty, or the ground-truth mask (truth_mask_score.h)
};

/// The ground-truth masks folder `options` asks for: its truth_masks_dir, or
/// RUN's input folder's masks/ when it has one and that is unset; "" for
/// none. Throws InputError naming a given folder that does not exist, or
/// the masks folder when options.masks is kTruth and there is none.
std::string truthMasksDirFor(const RunDirectory& run, const ExportOptions& options);

/// Calls `fuse` for every keyframe of `run` (time order) with its frame of
/// `source` (|dt| < 1e-4 s), loading each frame at most once (only the
/// keyframes' frames when options.frame_timestamps is given). The dynamic
/// mask follows options.masks: the run's dynamic_masks/<t>.png (none when
/// the file is missing), none, or the truth mask's people (label > 0).
/// truth_dir: from truthMasksDirFor; "" = no truth masks. Throws InputError
/// naming keyframes.txt if a keyframe has no frame, or a mask file that is
/// unreadable, not 8-bit single-channel or of the wrong size.
void forEachRunKeyframe(const RunDirectory& run, const FrameSource& source,
                        const ExportOptions& options, const std::string& truth_dir,
                        const std::function<void(const RunKeyframe&)>& fuse);

}  // namespace dynslam
