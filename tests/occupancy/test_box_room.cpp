// The OctoMap and the 2D grid of a synthetic box room (box_room.h) checked
// against the room's known geometry: occupied cells lie on its surfaces and
// cover the walls, cells along the keyframes' rays are free, nothing beyond
// the walls is known, and the grid's walls are the floor plan's, also when
// the world frame is tilted as a SLAM world frame is.
#include <gtest/gtest.h>

#include <cmath>

#include "box_room.h"
#include "mapexport/up_estimation.h"
#include "occupancy/level_frame.h"
#include "occupancy/occupancy_grid.h"
#include "occupancy/occupancy_map_builder.h"
#include "occupancy/octree_cells.h"

using namespace dynslam;
using dynslam::test::Box;
using dynslam::test::BoxRoom;

namespace {

DenseMapOptions denseOptions() {
  DenseMapOptions o;
  o.projection.max_depth = 6.0;  // the room's diagonal is 5.6 m
  return o;
}

struct BuiltRoom {
  std::unique_ptr<OccupancyMapBuilder> builder;
  LevelFrame level;
};

/// Builds the room's map; masks: the truth masks as dynamic masks.
BuiltRoom build(const BoxRoom& room, bool mask_person = false, bool truth = false,
                DenseMapOptions dense = denseOptions()) {
  BuiltRoom b;
  b.builder =
      std::make_unique<OccupancyMapBuilder>(BoxRoom::camera(), dense, OccupancyMapOptions{});
  for (std::size_t i = 0; i < room.size(); ++i) {
    const cv::Mat person = room.truthMask(i);
    b.builder->addKeyframe(room.frame(i), room.pose(i),
                           mask_person ? cv::Mat(person > 0) : cv::Mat(),
                           truth ? person : cv::Mat());
  }
  b.builder->build();
  MapData sample;
  sample.points = b.builder->surfacePoints();
  sample.keyframes = room.keyframes();
  b.level.R = levelRotation(estimateMapUp(sample).up);
  std::vector<double> heights;
  for (const auto& p : b.builder->surfacePoints()) {
    heights.push_back(b.level.R.row(2).dot(Eigen::Vector3d(p.x, p.y, p.z)));
  }
  estimateFloor(heights, 0.05, 0.5, b.level);
  return b;
}

Eigen::Vector3d centreOf(const octomap::OcTree& tree, const octomap::OcTreeKey& k) {
  const auto c = tree.keyToCoord(k);
  return {c.x(), c.y(), c.z()};
}

/// Occupied / free / unknown at a world point.
enum class State { kUnknown, kFree, kOccupied };
State stateAt(const octomap::OcTree& tree, const Eigen::Vector3d& p) {
  const octomap::OcTreeNode* n = tree.search(p.x(), p.y(), p.z());
  if (!n) return State::kUnknown;
  return tree.isNodeOccupied(n) ? State::kOccupied : State::kFree;
}

/// Points on the four walls between heights z0 and z1 (room frame), every 10 cm.
std::vector<Eigen::Vector3d> wallPoints(const BoxRoom& room, double z0, double z1) {
  std::vector<Eigen::Vector3d> pts;
  const auto& lo = room.room.lo;
  const auto& hi = room.room.hi;
  for (double z = z0; z <= z1; z += 0.1) {
    for (double x = lo.x() + 0.15; x < hi.x() - 0.15; x += 0.1) {
      pts.push_back({x, lo.y(), z});
      pts.push_back({x, hi.y(), z});
    }
    for (double y = lo.y() + 0.15; y < hi.y() - 0.15; y += 0.1) {
      pts.push_back({lo.x(), y, z});
      pts.push_back({hi.x(), y, z});
    }
  }
  return pts;
}

void checkOccupiedCellsLieOnSurfaces(const BoxRoom& room, const octomap::OcTree& tree) {
  const auto occupied = occupiedCells(tree);
  ASSERT_GT(occupied.size(), 3000u);
  // A cell holding a surface point has its centre within half a diagonal.
  const double reach = tree.getResolution() * std::sqrt(3.0) / 2 + 1e-3;
  std::size_t off_surface = 0;
  for (const auto& k : occupied) {
    off_surface += room.surfaceDistance(room.toRoom(centreOf(tree, k))) > reach;
  }
  EXPECT_EQ(off_surface, 0u) << "of " << occupied.size();
}

void checkWallsCovered(const BoxRoom& room, const octomap::OcTree& tree) {
  // The walls between 0.4 and 1.1 m are seen by at least three keyframes
  // (higher up only the far ones see them, and carving keeps only what three
  // keyframes confirm); the surface point is in one cell, which must be
  // occupied.
  std::size_t occupied = 0;
  const auto pts = wallPoints(room, 0.4, 1.1);
  for (const auto& p : pts) occupied += stateAt(tree, room.toWorld(p)) == State::kOccupied;
  EXPECT_GT(double(occupied) / pts.size(), 0.95) << occupied << " of " << pts.size();
}

void checkRaysAreFree(const BoxRoom& room, const octomap::OcTree& tree) {
  // Cells along the rays, at least 15 cm from any surface, are free.
  std::size_t samples = 0, free = 0, occupied = 0;
  for (std::size_t i = 0; i < room.size(); i += 3)
    for (int v = 2; v < 60; v += 7)
      for (int u = 3; u < 80; u += 9) {
        const BoxRoom::Hit h = room.castPixel(i, u, v);
        for (double s = 0.2; s < 0.95; s += 0.15) {
          const Eigen::Vector3d p = h.origin + s * (h.point - h.origin);
          if ((p - h.origin).norm() < 0.35 || room.surfaceDistance(p) < 0.15) continue;
          ++samples;
          const State st = stateAt(tree, room.toWorld(p));
          free += st == State::kFree;
          occupied += st == State::kOccupied;
        }
      }
  ASSERT_GT(samples, 500u);
  EXPECT_GT(double(free) / samples, 0.98) << free << " of " << samples;
  EXPECT_EQ(occupied, 0u);
}

void checkNothingKnownBeyondWalls(const BoxRoom& room, const octomap::OcTree& tree) {
  std::size_t outside = 0, known = 0;
  forEachCell(tree, [&](const octomap::OcTreeKey& k, bool) {
    ++known;
    outside += !room.room.contains(room.toRoom(centreOf(tree, k)), 0.09);
  });
  EXPECT_EQ(outside, 0u) << "of " << known;
  // Inside the cube nothing was seen either (>= 1 cell below its surface).
  std::size_t inside_cube = 0;
  forEachCell(tree, [&](const octomap::OcTreeKey& k, bool) {
    Box core = room.cube;
    core.lo.array() += 0.09;
    core.hi.array() -= 0.09;
    inside_cube += core.contains(room.toRoom(centreOf(tree, k)));
  });
  EXPECT_EQ(inside_cube, 0u);
}

/// The grid's cells against the floor plan: walls and the cube's sides are
/// occupied, the floor between them free, all in the level frame.
void checkGridAgainstFloorPlan(const BoxRoom& room, const BuiltRoom& b) {
  const OccupancyGrid2D grid = projectToGrid(b.builder->tree(), b.level, GridBand{0.10, 1.20});
  const double res = grid.resolution;
  auto cellAt = [&](const Eigen::Vector3d& p_room, std::int8_t& value) {
    const Eigen::Vector3d l = b.level.toLevel(room.toWorld(p_room));
    int ix, iy;
    if (!grid.cellOf(l.x(), l.y(), ix, iy)) return false;
    value = grid.at(ix, iy);
    return true;
  };
  // Walls at 0.6 m (every 10 cm along them) and the cube's sides.
  std::size_t wall = 0, wall_occupied = 0;
  std::vector<Eigen::Vector3d> pts = wallPoints(room, 0.6, 0.6);
  for (double t = 0.05; t < 0.5; t += 0.1) {
    const auto& lo = room.cube.lo;
    const auto& hi = room.cube.hi;
    pts.push_back({lo.x() + t, lo.y(), 0.3});
    pts.push_back({lo.x() + t, hi.y(), 0.3});
    pts.push_back({lo.x(), lo.y() + t, 0.3});
    pts.push_back({hi.x(), lo.y() + t, 0.3});
  }
  for (const auto& p : pts) {
    std::int8_t v;
    ++wall;
    wall_occupied += cellAt(p, v) && v == OccupancyGrid2D::kOccupied;
  }
  EXPECT_GT(double(wall_occupied) / wall, 0.97) << wall_occupied << " of " << wall;
  // The floor more than three cells from the walls and the cube: never
  // occupied; free where the keyframes looked (most of it). (An occupied
  // cell marks the grid cells within 0.45 cells of its centre, and in a
  // tilted frame that centre is up to 0.87 cells from the wall.)
  std::size_t floor = 0, floor_free = 0, floor_occupied = 0;
  for (double x = room.room.lo.x(); x < room.room.hi.x(); x += res / 2)
    for (double y = room.room.lo.y(); y < room.room.hi.y(); y += res / 2) {
      const Eigen::Vector3d p(x, y, 0.6);
      Box grown = room.cube;
      grown.lo.array() -= 3 * res;
      grown.hi.array() += 3 * res;
      if (!room.room.contains(p, -3 * res) || grown.contains(p)) continue;
      std::int8_t v;
      if (!cellAt(p, v)) continue;
      ++floor;
      floor_free += v == OccupancyGrid2D::kFree;
      floor_occupied += v == OccupancyGrid2D::kOccupied;
    }
  ASSERT_GT(floor, 10000u);
  EXPECT_EQ(floor_occupied, 0u) << "of " << floor;
  EXPECT_GT(double(floor_free) / floor, 0.9) << floor_free << " of " << floor;
  // Beyond the walls: unknown.
  std::size_t beyond = 0, beyond_known = 0;
  for (double x = -0.5; x < 4.5; x += res)
    for (double y : {-0.3, 3.3}) {
      std::int8_t v;
      if (!cellAt({x, y, 0.6}, v)) continue;
      ++beyond;
      beyond_known += v != OccupancyGrid2D::kUnknown;
    }
  EXPECT_EQ(beyond_known, 0u) << "of " << beyond;
}

}  // namespace

/// The plain room's map, built once for the tests that only read it.
const BuiltRoom& plainRoom() {
  static const BoxRoom room;
  static const BuiltRoom b = build(room);
  return b;
}

TEST(BoxRoomOctoMap, OccupiedAndFreeCellsMatchTheRoom) {
  const BoxRoom room;
  const BuiltRoom& b = plainRoom();
  const auto& tree = b.builder->tree();
  const OccupancyMapStats& s = b.builder->stats();
  EXPECT_EQ(s.keyframes, room.size());
  EXPECT_EQ(s.carved_dynamic, 0u);  // no dynamic masks: no dynamic votes
  checkOccupiedCellsLieOnSurfaces(room, tree);
  checkWallsCovered(room, tree);
  checkRaysAreFree(room, tree);
  checkNothingKnownBeyondWalls(room, tree);
}

TEST(BoxRoomOctoMap, FloorAndGridWallsMatchTheFloorPlan) {
  const BoxRoom room;
  const BuiltRoom& b = plainRoom();
  EXPECT_EQ(b.level.floor_source, "floor layer");
  EXPECT_NEAR(b.level.floor_height, BoxRoom::kFloorZ, 0.005);
  checkGridAgainstFloorPlan(room, b);
}

// The SLAM world frame is the first camera's: tilted ~40 deg and moved.
// Up and floor come from the map; the grid must still match the floor plan.
TEST(BoxRoomOctoMap, TiltedWorldFrame) {
  const mrpt::poses::CPose3D tilt(0.3, -0.7, 1.2, 0.4, -0.15, 0.7);  // x y z yaw pitch roll
  const BoxRoom room(false, tilt);
  const BuiltRoom b = build(room);
  const Eigen::Vector3d up_world = room.toWorld({0, 0, 1}) - room.toWorld({0, 0, 0});
  EXPECT_GT(b.level.R.row(2).dot(up_world), std::cos(2 * M_PI / 180));
  // Floor: the level height of the room's floor.
  const double floor_level = b.level.R.row(2).dot(room.toWorld({2, 1.5, BoxRoom::kFloorZ}));
  EXPECT_NEAR(b.level.floor_height, floor_level, 0.02);
  checkOccupiedCellsLieOnSurfaces(room, b.builder->tree());
  checkGridAgainstFloorPlan(room, b);
}

// A person standing in every keyframe: without masks they are in the map
// and inside the swept volume; with the true masks as dynamic masks the map
// has no cell of them, and the wall behind them stays.
TEST(BoxRoomOctoMap, MaskedPersonIsLeftOutAndSweptVolumeCountsThem) {
  const BoxRoom room(true);
  const BuiltRoom kept = build(room, /*mask_person=*/false, /*truth=*/true);
  const auto share_kept = kept.builder->sweptVolumeShare();
  ASSERT_TRUE(share_kept);
  // Occupied cells that can hold a point of the person's surface (known
  // geometry): every walker cell is one of them, and most of them are
  // walker cells (the rest hold only the floor under the person's feet).
  const auto& tk = kept.builder->tree();
  const double reach = tk.getResolution() * std::sqrt(3.0) / 2 + 1e-3;
  std::size_t near_person = 0;
  for (const auto& k : occupiedCells(tk))
    near_person += room.person.surfaceDistance(centreOf(tk, k)) < reach;
  EXPECT_GT(near_person, 100u);
  EXPECT_LE(share_kept->walker_points, near_person);
  EXPECT_GE(share_kept->walker_points, near_person * 8 / 10);
  EXPECT_EQ(share_kept->points, occupiedCells(tk).size());

  const BuiltRoom masked = build(room, /*mask_person=*/true, /*truth=*/true);
  const auto share = masked.builder->sweptVolumeShare();
  ASSERT_TRUE(share);
  EXPECT_EQ(share->walker_points, 0u);
  EXPECT_FALSE(masked.builder->sweptVolumeShare()->points == 0);
  const auto& tm = masked.builder->tree();
  std::size_t person_cells = 0;
  for (const auto& k : occupiedCells(tm)) {
    person_cells += room.person.surfaceDistance(centreOf(tm, k)) < 0.03 &&
                    room.room.surfaceDistance(centreOf(tm, k)) > 0.05;
  }
  EXPECT_EQ(person_cells, 0u);
  checkWallsCovered(room, tm);
}
