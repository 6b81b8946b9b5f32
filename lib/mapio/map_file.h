#pragma once
// The map file (OUT/map.dsm, documented in docs/map_file.md): a SLAM map
// saved so that a later run can localise in it or extend it. One versioned,
// little-endian binary file with a CRC-32 over its payload, holding what the
// map must match to be used again (camera, pyramid, vocabulary checksum) and
// the map itself: keyframes with their features (BoW vectors are rebuilt
// from the descriptors), map points with their observations, and the
// covisibility graph and spanning tree. Everything is written in id order,
// so saving a loaded map gives the same bytes again.
#include <cstdint>
#include <memory>
#include <string>

#include "map/frame_context.h"
#include "map/map.h"

namespace dynslam::mapio {

inline constexpr char kMapMagic[8] = {'D', 'Y', 'N', 'S', 'L', 'M', 'A', 'P'};
inline constexpr uint32_t kMapVersion = 1;
inline constexpr std::size_t kMapHeaderBytes = 32;

/// The whole file for the live keyframes and map points of `map`.
/// vocabulary_checksum: OrbVocabulary::checksum() of the vocabulary the
/// BoW vectors are to come from (0: none).
std::string encodeMap(const Map& map, const FrameContext& ctx, uint64_t vocabulary_checksum);
/// encodeMap() written atomically to path; throws std::runtime_error naming it.
void saveMap(const std::string& path, const Map& map, const FrameContext& ctx,
             uint64_t vocabulary_checksum);

struct LoadedMap {
  std::size_t file_bytes = 0, keyframes = 0, map_points = 0;
  uint32_t payload_crc = 0;  ///< as stored (and checked)
};

/// Reads the file at path into `map`, which must be empty; every keyframe's
/// features get `ctx`. Throws InputError(path, one line) on a missing,
/// truncated, corrupt (checksum) or wrong-version file and on a map made
/// with another camera, pyramid or vocabulary than ctx / vocabulary_checksum.
LoadedMap loadMap(const std::string& path, Map& map, std::shared_ptr<const FrameContext> ctx,
                  uint64_t vocabulary_checksum);

}  // namespace dynslam::mapio
