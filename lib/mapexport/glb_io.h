#pragma once
// glTF 2.0 binary (.glb) via assimp: viewable in any browser-based viewer
// (e.g. gltf-viewer, Blender) without a point-cloud tool.
//
// Layout of the scene (names are the contract with readGlb):
//   mesh "dense_map"  : POINTS primitive, vertex colours (COLOR_0)
//   mesh "trajectory" : LINES primitive, keyframe positions in order
//   mesh "frustums"   : LINES primitive, one wireframe pyramid per keyframe
//   nodes "keyframe_<t>" : empty nodes whose transform is the keyframe's
//                          camera-to-world pose (t = timestamp, 6 decimals),
//                          so the full poses survive a round trip.
#include <string>

#include "mapexport/map_data.h"

namespace dynslam {

void writeGlb(const std::string& path, const MapData& map, const MapWriteOptions& options);

/// Throws InputError naming the file if assimp cannot read it or it has no
/// "dense_map" mesh.
MapData readGlb(const std::string& path);

}  // namespace dynslam
