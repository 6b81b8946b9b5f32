#include "mapexport/glb_io.h"

#include <assimp/scene.h>
#include <assimp/Exporter.hpp>
#include <assimp/Importer.hpp>

#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "mapexport/up_estimation.h"

namespace dynslam {
namespace {

constexpr const char* kRootName = "dynslam_map";
constexpr const char* kPointsName = "dense_map";
constexpr const char* kTrajectoryName = "trajectory";
constexpr const char* kFrustumsName = "frustums";
constexpr const char* kKeyframePrefix = "keyframe_";

aiVector3D toAi(const mrpt::math::TPoint3D& p) {
  return aiVector3D(float(p.x), float(p.y), float(p.z));
}
aiVector3D position(const mrpt::poses::CPose3D& pose) {
  return aiVector3D(float(pose.x()), float(pose.y()), float(pose.z()));
}

/// A mesh of `n_per_face`-vertex primitives (1 = points, 2 = lines) over the
/// vertices in order. Point meshes get no faces: glTF draws a POINTS
/// primitive without indices, and leaving out one aiFace (a heap array) per
/// point makes assimp's export (scene copy, JoinIdenticalVertices) several
/// times faster and smaller on multi-million-point maps.
aiMesh* makeMesh(const char* name, const std::vector<aiVector3D>& vertices,
                 const std::vector<aiColor4D>& colors, unsigned n_per_face) {
  auto* mesh = new aiMesh();
  mesh->mName = aiString(name);
  mesh->mPrimitiveTypes = n_per_face == 1 ? aiPrimitiveType_POINT : aiPrimitiveType_LINE;
  mesh->mMaterialIndex = 0;
  mesh->mNumVertices = static_cast<unsigned>(vertices.size());
  mesh->mVertices = new aiVector3D[vertices.size()];
  std::copy(vertices.begin(), vertices.end(), mesh->mVertices);
  mesh->mColors[0] = new aiColor4D[vertices.size()];
  std::copy(colors.begin(), colors.end(), mesh->mColors[0]);
  if (n_per_face == 1) return mesh;
  mesh->mNumFaces = static_cast<unsigned>(vertices.size() / n_per_face);
  mesh->mFaces = new aiFace[mesh->mNumFaces];
  for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
    mesh->mFaces[f].mNumIndices = n_per_face;
    mesh->mFaces[f].mIndices = new unsigned[n_per_face];
    for (unsigned k = 0; k < n_per_face; ++k) mesh->mFaces[f].mIndices[k] = f * n_per_face + k;
  }
  return mesh;
}

aiMatrix4x4 toAiMatrix(const mrpt::poses::CPose3D& pose) {
  const auto& R = pose.getRotationMatrix();
  return aiMatrix4x4(float(R(0, 0)), float(R(0, 1)), float(R(0, 2)), float(pose.x()),
                     float(R(1, 0)), float(R(1, 1)), float(R(1, 2)), float(pose.y()),
                     float(R(2, 0)), float(R(2, 1)), float(R(2, 2)), float(pose.z()), 0, 0, 0, 1);
}

/// Rotation taking the map's up direction (estimateMapUp) to +Y, glTF's up axis, so
/// generic viewers show the map upright. Applied on the root node only; the
/// data below it stays in world coordinates (readGlb ignores the root).
aiMatrix4x4 uprightRoot(const MapData& map) {
  const auto up = estimateMapUp(map).up;
  const aiVector3D from{float(up[0]), float(up[1]), float(up[2])};
  const aiVector3D to{0.f, 1.f, 0.f};
  aiMatrix4x4 m;
  aiMatrix4x4::FromToMatrix(from, to, m);
  return m;
}

std::vector<aiVector3D> frustumSegments(const Trajectory& keyframes,
                                        const MapWriteOptions& options) {
  PinholeCamera cam = options.camera;
  if (cam.fx <= 0 || cam.fy <= 0) {  // 4:3 image, 60 deg horizontal FOV
    cam.width = 640;
    cam.height = 480;
    cam.fx = cam.fy = 320.0 / std::tan(M_PI / 6);
    cam.cx = 320;
    cam.cy = 240;
  }
  const double d = options.frustum_depth;
  const double us[4] = {0, double(cam.width), double(cam.width), 0};
  const double vs[4] = {0, 0, double(cam.height), double(cam.height)};
  std::vector<aiVector3D> v;
  for (const auto& kf : keyframes) {
    mrpt::math::TPoint3D corners[4];
    for (int c = 0; c < 4; ++c) {
      kf.pose.composePoint((us[c] - cam.cx) / cam.fx * d, (vs[c] - cam.cy) / cam.fy * d, d,
                           corners[c].x, corners[c].y, corners[c].z);
    }
    const auto apex = position(kf.pose);
    for (int c = 0; c < 4; ++c) {
      v.push_back(apex);
      v.push_back(toAi(corners[c]));
      v.push_back(toAi(corners[c]));
      v.push_back(toAi(corners[(c + 1) % 4]));
    }
  }
  return v;
}

}  // namespace

void writeGlb(const std::string& path, const MapData& map, const MapWriteOptions& options) {
  // assimp's exporter crashed on a mesh without vertices (found by fuzzing).
  if (map.points.empty()) throw std::runtime_error(path + ": " + kEmptyMapMessage);
  auto scene = std::make_unique<aiScene>();
  scene->mNumMaterials = 1;
  scene->mMaterials = new aiMaterial*[1];
  scene->mMaterials[0] = new aiMaterial();
  const aiString material_name("vertex_colour");
  scene->mMaterials[0]->AddProperty(&material_name, AI_MATKEY_NAME);

  std::vector<aiMesh*> meshes;
  {
    std::vector<aiVector3D> v;
    std::vector<aiColor4D> c;
    v.reserve(map.points.size());
    c.reserve(map.points.size());
    for (const auto& p : map.points) {
      v.emplace_back(p.x, p.y, p.z);
      c.emplace_back(p.r / 255.f, p.g / 255.f, p.b / 255.f, 1.f);
    }
    meshes.push_back(makeMesh(kPointsName, v, c, 1));
  }
  if (map.keyframes.size() >= 2) {
    std::vector<aiVector3D> v;
    for (std::size_t i = 0; i + 1 < map.keyframes.size(); ++i) {
      v.push_back(position(map.keyframes[i].pose));
      v.push_back(position(map.keyframes[i + 1].pose));
    }
    meshes.push_back(
        makeMesh(kTrajectoryName, v, std::vector<aiColor4D>(v.size(), {1, 0, 0, 1}), 2));
  }
  if (!map.keyframes.empty()) {
    const auto v = frustumSegments(map.keyframes, options);
    meshes.push_back(makeMesh(kFrustumsName, v, std::vector<aiColor4D>(v.size(), {0, 0, 1, 1}), 2));
  }
  scene->mNumMeshes = static_cast<unsigned>(meshes.size());
  scene->mMeshes = new aiMesh*[meshes.size()];
  std::copy(meshes.begin(), meshes.end(), scene->mMeshes);

  auto* root = new aiNode(kRootName);
  root->mTransformation = uprightRoot(map);
  scene->mRootNode = root;
  std::vector<aiNode*> children;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    auto* node = new aiNode(scene->mMeshes[m]->mName.C_Str());
    node->mNumMeshes = 1;
    node->mMeshes = new unsigned[1]{m};
    children.push_back(node);
  }
  for (const auto& kf : map.keyframes) {
    char name[64];
    std::snprintf(name, sizeof(name), "%s%.6f", kKeyframePrefix, kf.timestamp);
    auto* node = new aiNode(name);
    node->mTransformation = toAiMatrix(kf.pose);
    children.push_back(node);
  }
  root->addChildren(static_cast<unsigned>(children.size()), children.data());

  // Encoded in memory and written by us: assimp's own file writer does not
  // report a full disk, which would leave a cut .glb under the final name.
  Assimp::Exporter exporter;
  const aiExportDataBlob* blob = exporter.ExportToBlob(scene.get(), "glb2");
  if (!blob || blob->next) {
    throw std::runtime_error(path + ": cannot write glTF (" + exporter.GetErrorString() + ")");
  }
  writeFileAtomically(
      path,
      [&](std::ostream& out) {
        out.write(static_cast<const char*>(blob->data), static_cast<std::streamsize>(blob->size));
      },
      true);
}

MapData readGlb(const std::string& path) {
  requireRegularFile(path, "glTF (.glb) file");
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(path, 0);
  if (!scene || !scene->mRootNode) {
    throw InputError(path, std::string("cannot read glTF (") + importer.GetErrorString() + ")");
  }
  MapData map;
  bool found = false;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* mesh = scene->mMeshes[m];
    if (std::string(mesh->mName.C_Str()) != kPointsName) continue;
    found = true;
    map.points.reserve(map.points.size() + mesh->mNumVertices);
    for (unsigned i = 0; i < mesh->mNumVertices; ++i) {
      ColoredPoint p;
      p.x = mesh->mVertices[i].x;
      p.y = mesh->mVertices[i].y;
      p.z = mesh->mVertices[i].z;
      if (mesh->mColors[0]) {
        const auto& c = mesh->mColors[0][i];
        auto u8 = [](float f) {
          return std::uint8_t(std::lround(std::min(1.f, std::max(0.f, f)) * 255.f));
        };
        p.r = u8(c.r);
        p.g = u8(c.g);
        p.b = u8(c.b);
      }
      map.points.push_back(p);
    }
  }
  if (!found) throw InputError(path, std::string("no \"") + kPointsName + "\" mesh");

  // Keyframe poses: the "keyframe_<t>" nodes, in file order.
  const std::string prefix = kKeyframePrefix;
  std::vector<const aiNode*> stack{scene->mRootNode};
  std::vector<const aiNode*> nodes;
  while (!stack.empty()) {  // depth-first, children in order
    const aiNode* n = stack.back();
    stack.pop_back();
    nodes.push_back(n);
    for (unsigned c = n->mNumChildren; c-- > 0;) stack.push_back(n->mChildren[c]);
  }
  for (const aiNode* n : nodes) {
    const std::string name = n->mName.C_Str();
    if (name.compare(0, prefix.size(), prefix) != 0) continue;
    const aiMatrix4x4& t = n->mTransformation;
    mrpt::math::CMatrixDouble44 h;
    for (unsigned r = 0; r < 4; ++r)
      for (unsigned c = 0; c < 4; ++c) h(r, c) = t[r][c];
    StampedPose kf;
    try {
      kf.timestamp = std::stod(name.substr(prefix.size()));
    } catch (const std::exception&) {
      throw InputError(path, "bad keyframe node name \"" + name + "\"");
    }
    kf.pose = mrpt::poses::CPose3D(h);
    map.keyframes.push_back(kf);
  }
  return map;
}

}  // namespace dynslam
