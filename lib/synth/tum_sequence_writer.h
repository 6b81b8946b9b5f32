#pragma once
// Writes a synthetic sequence as a TUM RGB-D folder that `dynslam run` reads
// like a real one: rgb/ (PNG), depth/ (16-bit PNG), rgb.txt, depth.txt,
// groundtruth.txt (camera-to-world, "t tx ty tz qx qy qz qw"), camera.yaml
// (its intrinsics; picked up by the sequence reader) and, with movers,
// masks/<timestamp>.png (0 static, k mover k, as ../shared's composites).
// The folder is staged and renamed into place: a failed write leaves nothing.
#include <functional>
#include <string>

namespace dynslam::synth {

class SyntheticSequence;

/// progress(i, n) after each frame (optional). Returns the frames written.
int writeTumSequence(SyntheticSequence& seq, const std::string& out_dir,
                     const std::function<void(int, int)>& progress = {});

}  // namespace dynslam::synth
