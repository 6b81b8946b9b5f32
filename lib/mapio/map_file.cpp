#include "mapio/map_file.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

#include "core/atomic_file.h"
#include "core/checksum.h"
#include "core/errors.h"
#include "core/map_bounds.h"
#include "mapio/byte_stream.h"

namespace dynslam::mapio {

namespace {

// Header field offsets (docs/map_file.md).
constexpr std::size_t kOffVersion = 8, kOffHeaderBytes = 12, kOffPayloadBytes = 16, kOffCrc = 24;
constexpr std::size_t kDescriptorBytes = 32;

/// Map content the file refers to but does not hold: a file that passed its
/// checksum yet does not make sense (written by a broken program).
class CorruptMap : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Every number of a map is finite: a NaN pose that passed the checksum was
/// loaded and reached the trajectory (found by fuzzing).
double finite(double v) {
  if (!std::isfinite(v)) throw CorruptMap("a non-finite number (" + std::to_string(v) + ")");
  return v;
}
float finite(float v) { return static_cast<float>(finite(static_cast<double>(v))); }

/// A position, distance or depth of a map lies within kMaxMapCoordinate of
/// the origin (core/map_bounds.h): points at 1e300 m passed the finiteness
/// check (issue 57).
double bounded(double v, const char* what) {
  if (!(std::abs(finite(v)) <= kMaxMapCoordinate)) {
    std::ostringstream s;
    s << what << " of " << v << " m, beyond the " << kMaxMapCoordinate / 1000 << " km a map spans";
    throw CorruptMap(s.str());
  }
  return v;
}

/// How far a saved rotation may be from a rotation: tracking composes poses
/// that leave SO(3) by rounding only (1e-15 per step), while a matrix that
/// is not a rotation at all (a scale, a shear, a reflection) is off by
/// tenths.
constexpr double kRotationTolerance = 1e-6;

void writePose(ByteWriter& w, const mrpt::poses::CPose3D& wc) {
  const auto H = wc.getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) w.f64(H(r, c));
}

mrpt::poses::CPose3D readPose(ByteReader& r) {
  mrpt::math::CMatrixDouble44 H;
  H.setIdentity();
  for (int i = 0; i < 3; ++i)
    for (int c = 0; c < 4; ++c)
      H(i, c) = c == 3 ? bounded(r.f64(), "a keyframe position") : finite(r.f64());
  // The rotation block must be orthonormal with determinant +1 (a keyframe
  // pose that is no rotation was loaded, issue 57).
  double off = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double dot = 0;
      for (int k = 0; k < 3; ++k) dot += H(k, i) * H(k, j);
      off = std::max(off, std::abs(dot - (i == j ? 1.0 : 0.0)));
    }
  const double det = H(0, 0) * (H(1, 1) * H(2, 2) - H(1, 2) * H(2, 1)) -
                     H(0, 1) * (H(1, 0) * H(2, 2) - H(1, 2) * H(2, 0)) +
                     H(0, 2) * (H(1, 0) * H(2, 1) - H(1, 1) * H(2, 0));
  if (!(off <= kRotationTolerance) || !(det > 0))
    throw CorruptMap("a keyframe pose whose rotation is not a rotation (R'R - I off by " +
                     std::to_string(off) + ", det " + std::to_string(det) + ")");
  return mrpt::poses::CPose3D(H);
}

void writeKeyPoints(ByteWriter& w, const std::vector<cv::KeyPoint>& keys) {
  for (const cv::KeyPoint& k : keys) {
    w.f32(k.pt.x);
    w.f32(k.pt.y);
    w.f32(k.size);
    w.f32(k.angle);
    w.f32(k.response);
    w.i32(k.octave);
    w.i32(k.class_id);
  }
}

/// Where keypoints may lie: the image for detected ones; undistorted ones
/// within one image size around it (undistortion moves them by far less).
struct KeyPointArea {
  float min_x, max_x, min_y, max_y;
  static KeyPointArea image(const PinholeCamera& c) {
    return {0, float(c.width), 0, float(c.height)};
  }
  static KeyPointArea aroundImage(const PinholeCamera& c) {
    return {-float(c.width), 2 * float(c.width), -float(c.height), 2 * float(c.height)};
  }
};

std::vector<cv::KeyPoint> readKeyPoints(ByteReader& r, std::size_t n, int levels,
                                        const KeyPointArea& area) {
  std::vector<cv::KeyPoint> keys(n);
  for (cv::KeyPoint& k : keys) {
    k.pt.x = finite(r.f32());
    k.pt.y = finite(r.f32());
    k.size = finite(r.f32());
    k.angle = finite(r.f32());
    k.response = finite(r.f32());
    k.octave = r.i32();
    k.class_id = r.i32();
    if (k.octave < 0 || k.octave >= levels) throw CorruptMap("keypoint octave out of range");
    if (!(k.pt.x >= area.min_x && k.pt.x < area.max_x && k.pt.y >= area.min_y &&
          k.pt.y < area.max_y)) {
      std::ostringstream s;
      s << "a keypoint at (" << k.pt.x << ", " << k.pt.y << ") px, outside the image";
      throw CorruptMap(s.str());
    }
  }
  return keys;
}

constexpr std::size_t kKeyPointBytes = 7 * 4;

void writeFeatures(ByteWriter& w, const FeatureSet& f) {
  const std::size_t n = f.size();
  if (f.keys_un.size() != n || f.depth.size() != n || f.ur.size() != n || f.dynamic.size() != n ||
      static_cast<std::size_t>(f.descriptors.rows) != n ||
      (!f.colors.empty() && f.colors.size() != n))
    throw std::logic_error("encodeMap: a keyframe's feature arrays differ in size");
  w.u32(static_cast<uint32_t>(n));
  w.u8(f.colors.empty() ? 0 : 1);
  writeKeyPoints(w, f.keys);
  writeKeyPoints(w, f.keys_un);
  for (std::size_t i = 0; i < n; ++i) w.bytes(f.descriptor(i), kDescriptorBytes);
  for (float d : f.depth) w.f32(d);
  for (float u : f.ur) w.f32(u);
  for (uint8_t d : f.dynamic) w.u8(d);
  for (const cv::Vec3b& c : f.colors) w.bytes(&c[0], 3);
}

std::shared_ptr<FeatureSet> readFeatures(ByteReader& r, std::shared_ptr<const FrameContext> ctx) {
  auto f = std::make_shared<FeatureSet>();
  f->ctx = ctx;
  const std::size_t n = r.count(2 * kKeyPointBytes + kDescriptorBytes + 9);
  const bool colors = r.u8() != 0;
  f->keys = readKeyPoints(r, n, ctx->levels, KeyPointArea::image(ctx->camera));
  f->keys_un = readKeyPoints(r, n, ctx->levels, KeyPointArea::aroundImage(ctx->camera));
  f->descriptors = cv::Mat(static_cast<int>(n), static_cast<int>(kDescriptorBytes), CV_8UC1);
  for (std::size_t i = 0; i < n; ++i)
    r.bytes(f->descriptors.ptr<uint8_t>(static_cast<int>(i)), kDescriptorBytes);
  f->depth.resize(n);
  for (float& d : f->depth) d = float(bounded(r.f32(), "a keypoint depth"));
  f->ur.resize(n);
  for (float& u : f->ur) u = finite(r.f32());
  f->dynamic.resize(n);
  for (uint8_t& d : f->dynamic) d = r.u8();
  if (colors) {
    f->colors.resize(n);
    for (cv::Vec3b& c : f->colors) r.bytes(&c[0], 3);
  }
  f->buildGrids();
  return f;
}

std::string cameraText(const PinholeCamera& c, double bf, int levels, double scale) {
  std::ostringstream s;
  s << c.width << "x" << c.height << " fx " << c.fx << " fy " << c.fy << " cx " << c.cx << " cy "
    << c.cy << " dist " << c.dist[0] << "," << c.dist[1] << "," << c.dist[2] << "," << c.dist[3]
    << "," << c.dist[4] << " bf " << bf << ", " << levels << " levels x " << scale;
  return s.str();
}

void writeIdentity(ByteWriter& w, const FrameContext& ctx, uint64_t vocabulary_checksum) {
  const PinholeCamera& c = ctx.camera;
  w.i32(c.width);
  w.i32(c.height);
  for (double v : {c.fx, c.fy, c.cx, c.cy}) w.f64(v);
  for (double d : c.dist) w.f64(d);
  w.f64(ctx.proj.bf);
  w.i32(ctx.levels);
  w.f32(ctx.scale_factor);
  w.u64(vocabulary_checksum);
}

/// Throws InputError(path) when the map was made for another camera,
/// pyramid or vocabulary than this run's.
void checkIdentity(ByteReader& r, const std::string& path, const FrameContext& ctx,
                   uint64_t vocabulary_checksum) {
  PinholeCamera c;
  c.width = r.i32();
  c.height = r.i32();
  c.fx = finite(r.f64());
  c.fy = finite(r.f64());
  c.cx = finite(r.f64());
  c.cy = finite(r.f64());
  for (double& d : c.dist) d = finite(r.f64());
  const double bf = finite(r.f64());
  const int levels = r.i32();
  const float scale = finite(r.f32());
  const uint64_t voc = r.u64();
  if (!c.sameGeometry(ctx.camera) || bf != ctx.proj.bf || levels != ctx.levels ||
      scale != ctx.scale_factor)
    throw InputError(path, "map made for another camera (" + cameraText(c, bf, levels, scale) +
                               ") than this run's (" +
                               cameraText(ctx.camera, ctx.proj.bf, ctx.levels, ctx.scale_factor) +
                               ")");
  if (voc != vocabulary_checksum) {
    std::ostringstream s;
    s << std::hex << "map made with another vocabulary (checksum " << voc
      << ") than the configured one (" << vocabulary_checksum << ")";
    throw InputError(path, s.str());
  }
}

template <typename T>
std::vector<T*> byId(std::vector<T*> v) {
  std::sort(v.begin(), v.end(), [](const T* a, const T* b) { return a->id < b->id; });
  return v;
}

}  // namespace

std::string encodeMap(const Map& map, const FrameContext& ctx, uint64_t vocabulary_checksum) {
  const std::vector<KeyFrame*> kfs = byId(map.keyFrames());
  const std::vector<MapPoint*> points = byId(map.mapPoints());
  std::unordered_map<const KeyFrame*, bool> saved;
  for (const KeyFrame* kf : kfs) saved[kf] = true;
  auto isSaved = [&](const KeyFrame* kf) { return kf && saved.count(kf) > 0; };
  std::unordered_map<const MapPoint*, bool> saved_points;
  for (const MapPoint* p : points) saved_points[p] = true;

  ByteWriter w;
  w.bytes(kMapMagic, sizeof kMapMagic);
  w.u32(kMapVersion);
  w.u32(static_cast<uint32_t>(kMapHeaderBytes));
  w.u64(0);  // payload bytes, patched below
  w.u32(0);  // CRC-32, patched below
  w.u32(0);  // reserved
  writeIdentity(w, ctx, vocabulary_checksum);
  w.i64(map.nextKeyFrameId());
  w.i64(map.nextMapPointId());

  w.u32(static_cast<uint32_t>(kfs.size()));
  for (const KeyFrame* kf : kfs) {
    w.i64(kf->id);
    w.i64(kf->frame_id);
    w.f64(kf->timestamp);
    w.u64(kf->frame_index);
    writePose(w, kf->pose.wc());
    w.u8(kf->keep ? 1 : 0);
    writeFeatures(w, kf->f());
  }

  w.u32(static_cast<uint32_t>(points.size()));
  for (const MapPoint* p : points) {
    w.i64(p->id);
    for (int k = 0; k < 3; ++k) w.f64(p->pos[k]);
    const bool has_desc = !p->descriptor.empty();
    w.u8(has_desc ? 1 : 0);
    if (has_desc) w.bytes(p->descriptor.ptr<uint8_t>(), kDescriptorBytes);
    for (int k = 0; k < 3; ++k) w.f64(p->normal[k]);
    w.f32(p->min_dist);
    w.f32(p->max_dist);
    std::vector<std::pair<const KeyFrame*, int>> obs;
    for (const auto& [kf, idx] : p->obs)
      if (isSaved(kf)) obs.emplace_back(kf, idx);
    // A reference keyframe that is gone is replaced as eraseObservation does.
    const KeyFrame* ref =
        isSaved(p->ref_kf) ? p->ref_kf : (obs.empty() ? nullptr : obs.front().first);
    w.i64(ref ? ref->id : -1);
    w.i64(p->first_kf_id);
    w.i32(p->visible);
    w.i32(p->found);
    w.i32(p->dynamic_hits);
    w.u32(static_cast<uint32_t>(obs.size()));
    for (const auto& [kf, idx] : obs) {
      w.i64(kf->id);
      w.u32(static_cast<uint32_t>(idx));
    }
  }

  // Per keyframe: its keypoint -> map point links, parent and covisibility edges.
  for (const KeyFrame* kf : kfs) {
    std::vector<std::pair<uint32_t, long>> links;
    for (std::size_t i = 0; i < kf->points.size(); ++i)
      if (kf->points[i] && saved_points.count(kf->points[i]))
        links.emplace_back(i, kf->points[i]->id);
    w.u32(static_cast<uint32_t>(links.size()));
    for (const auto& [i, id] : links) {
      w.u32(i);
      w.i64(id);
    }
    w.i64(isSaved(kf->parent) ? kf->parent->id : -1);
    std::vector<std::pair<long, int>> edges;
    for (const auto& [other, weight] : kf->connections())
      if (isSaved(other)) edges.emplace_back(other->id, weight);
    w.u32(static_cast<uint32_t>(edges.size()));
    for (const auto& [id, weight] : edges) {
      w.i64(id);
      w.i32(weight);
    }
  }

  w.patchU64(kOffPayloadBytes, w.size() - kMapHeaderBytes);
  std::string out = w.release();
  const uint32_t crc = crc32Of(out, kMapHeaderBytes);
  for (int i = 0; i < 4; ++i) out[kOffCrc + i] = static_cast<char>((crc >> (8 * i)) & 0xff);
  return out;
}

void saveMap(const std::string& path, const Map& map, const FrameContext& ctx,
             uint64_t vocabulary_checksum) {
  const std::string bytes = encodeMap(map, ctx, vocabulary_checksum);
  writeFileAtomically(
      path,
      [&](std::ostream& os) { os.write(bytes.data(), static_cast<std::streamsize>(bytes.size())); },
      true);
}

namespace {

void checkHeader(const std::string& path, const std::string& bytes) {
  if (bytes.size() < sizeof kMapMagic ||
      std::memcmp(bytes.data(), kMapMagic, sizeof kMapMagic) != 0)
    throw InputError(path, "not a dynslam map file (no DYNSLMAP header)");
  if (bytes.size() < kMapHeaderBytes)
    throw InputError(path, "truncated map file: " + std::to_string(bytes.size()) +
                               " bytes, shorter than its header");
  ByteReader at_version(std::string_view(bytes).substr(kOffVersion));
  const uint32_t version = at_version.u32();
  if (version != kMapVersion)
    throw InputError(path, "map file version " + std::to_string(version) +
                               ", this dynslam reads version " + std::to_string(kMapVersion));
  const uint32_t header_bytes = at_version.u32();
  const uint64_t payload = at_version.u64();
  const uint32_t crc = at_version.u32();
  if (header_bytes != kMapHeaderBytes) throw InputError(path, "corrupt map file header");
  if (bytes.size() - kMapHeaderBytes < payload)
    throw InputError(path, "truncated map file: " + std::to_string(bytes.size()) +
                               " bytes, its header announces " + std::to_string(payload) +
                               " bytes after the " + std::to_string(kMapHeaderBytes) +
                               "-byte header");
  if (bytes.size() - kMapHeaderBytes > payload)
    throw InputError(
        path, "corrupt map file: " + std::to_string(bytes.size() - kMapHeaderBytes - payload) +
                  " bytes after the end of the map");
  if (crc32Of(bytes, kMapHeaderBytes) != crc)
    throw InputError(path, "checksum mismatch: the map file is corrupt");
}

void readMapBody(ByteReader& r, Map& map, std::shared_ptr<const FrameContext> ctx) {
  const long next_kf = r.i64();
  const long next_point = r.i64();
  std::map<long, KeyFrame*> kfs;
  std::vector<KeyFrame*> kf_order;
  const uint32_t n_kf = r.count(8 * 4 + 12 * 8);
  for (uint32_t k = 0; k < n_kf; ++k) {
    const long id = r.i64();
    const long frame_id = r.i64();
    const double timestamp = finite(r.f64());
    const std::size_t frame_index = r.u64();
    const CameraPose pose = CameraPose::exact(readPose(r));
    const bool keep = r.u8() != 0;
    KeyFrame* kf =
        map.restoreKeyFrame(id, frame_id, timestamp, frame_index, readFeatures(r, ctx), pose);
    kf->keep = keep;
    kfs[id] = kf;
    kf_order.push_back(kf);
  }
  auto keyframe = [&](long id) -> KeyFrame* {
    if (id < 0) return nullptr;
    auto it = kfs.find(id);
    if (it == kfs.end()) throw CorruptMap("unknown keyframe id " + std::to_string(id));
    return it->second;
  };
  std::map<long, MapPoint*> points;
  const uint32_t n_points = r.count(8 + 24 + 1 + 24 + 8 + 16 + 12 + 4);
  for (uint32_t k = 0; k < n_points; ++k) {
    const long id = r.i64();
    Eigen::Vector3d pos;
    for (int i = 0; i < 3; ++i) pos[i] = bounded(r.f64(), "a map point position");
    cv::Mat desc;
    if (r.u8()) {
      desc = cv::Mat(1, static_cast<int>(kDescriptorBytes), CV_8UC1);
      r.bytes(desc.ptr<uint8_t>(), kDescriptorBytes);
    }
    Eigen::Vector3d normal;
    for (int i = 0; i < 3; ++i) normal[i] = finite(r.f64());
    const float min_dist = float(bounded(r.f32(), "a map point's minimum distance"));
    const float max_dist = float(bounded(r.f32(), "a map point's maximum distance"));
    KeyFrame* ref = keyframe(r.i64());
    MapPoint* p = map.restoreMapPoint(id, pos, ref);
    p->descriptor = desc;
    p->normal = normal;
    p->min_dist = min_dist;
    p->max_dist = max_dist;
    p->first_kf_id = r.i64();
    p->visible = r.i32();
    p->found = r.i32();
    p->dynamic_hits = r.i32();
    const uint32_t n_obs = r.count(12);
    for (uint32_t o = 0; o < n_obs; ++o) {
      KeyFrame* kf = keyframe(r.i64());
      const uint32_t idx = r.u32();
      if (!kf || idx >= kf->f().size()) throw CorruptMap("observation of a missing keypoint");
      p->addObservation(kf, static_cast<int>(idx));
    }
    points[id] = p;
  }
  for (KeyFrame* kf : kf_order) {
    const uint32_t n_links = r.count(12);
    for (uint32_t l = 0; l < n_links; ++l) {
      const uint32_t idx = r.u32();
      const long id = r.i64();
      auto it = points.find(id);
      if (idx >= kf->points.size() || it == points.end())
        throw CorruptMap("keyframe link to a missing keypoint or map point");
      kf->addPoint(it->second, static_cast<int>(idx));
    }
    KeyFrame* parent = keyframe(r.i64());
    std::map<KeyFrame*, int, KeyFrameIdLess> edges;
    const uint32_t n_edges = r.count(12);
    for (uint32_t e = 0; e < n_edges; ++e) {
      KeyFrame* other = keyframe(r.i64());
      edges[other] = r.i32();
    }
    kf->restoreGraph(parent, edges);
  }
  map.restoreNextIds(next_kf, next_point);
  if (r.remaining() != 0) throw CorruptMap("bytes left after the map");
}

}  // namespace

LoadedMap loadMap(const std::string& path, Map& map, std::shared_ptr<const FrameContext> ctx,
                  uint64_t vocabulary_checksum) {
  if (map.keyFrameCount() != 0 || map.mapPointCount() != 0)
    throw std::logic_error("loadMap: the map must be empty");
  // A device or a pipe is refused (/dev/zero: read until memory ran out; a FIFO: blocked).
  const std::string bytes = readRegularFile(path, "map file");
  checkHeader(path, bytes);
  ByteReader r(std::string_view(bytes).substr(kMapHeaderBytes));
  try {
    checkIdentity(r, path, *ctx, vocabulary_checksum);
    readMapBody(r, map, ctx);
  } catch (const TruncatedInput& e) {
    throw InputError(path, std::string("corrupt map file: ") + e.what());
  } catch (const CorruptMap& e) {
    throw InputError(path, std::string("corrupt map file: ") + e.what());
  } catch (const std::invalid_argument& e) {
    throw InputError(path, std::string("corrupt map file: ") + e.what());
  }
  LoadedMap info;
  info.file_bytes = bytes.size();
  info.keyframes = map.keyFrameCount();
  info.map_points = map.mapPointCount();
  info.payload_crc = crc32Of(bytes, kMapHeaderBytes);
  return info;
}

}  // namespace dynslam::mapio
