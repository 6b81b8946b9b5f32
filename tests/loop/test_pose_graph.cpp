// PoseGraph conventions on graphs small enough to solve by hand: an edge
// i -> j is the pose of j seen from i, fixed nodes stay put, duplicates are
// refused.
#include <gtest/gtest.h>

#include <cmath>

#include "loop/pose_graph.h"

using dynslam::loop::PoseGraph;
using mrpt::poses::CPose3D;

namespace {

double poseDistance(const CPose3D& a, const CPose3D& b) {
  const CPose3D d = a - b;
  return d.translation().norm() + std::abs(d.yaw()) + std::abs(d.pitch()) + std::abs(d.roll());
}

}  // namespace

// Node 0 fixed at a non-trivial pose, node 1 starts at the origin: after the
// optimisation node 1 must sit at P0 (+) T_01, which pins the edge direction.
TEST(PoseGraph, TwoNodesEdgeIsPoseOfSecondInFirst) {
  PoseGraph g;
  const CPose3D P0(1.0, -2.0, 0.5, 0.4, -0.1, 0.2);
  const CPose3D T01(0.5, 0.3, -0.2, 0.3, 0.05, -0.1);
  g.addNode(0, P0);
  g.addNode(1, CPose3D());
  ASSERT_TRUE(g.addEdge(0, 1, T01));
  g.fix(0);
  const auto r = g.optimize(50);
  ASSERT_TRUE(r.ok);
  EXPECT_GT(r.initial_sq_error, 0.1);
  EXPECT_LT(r.final_sq_error, 1e-12);
  EXPECT_LT(poseDistance(g.pose(1), P0 + T01), 1e-6);
  EXPECT_LT(poseDistance(g.pose(0), P0), 1e-12);  // fixed
}

// The same edge, with node 1 fixed: node 0 goes to P1 (-) T01.
TEST(PoseGraph, FixingTheSecondNodeMovesTheFirst) {
  PoseGraph g;
  const CPose3D P1(3.0, 1.0, -1.0, -0.7, 0.2, 0.1);
  const CPose3D T01(0.5, 0.3, -0.2, 0.3, 0.05, -0.1);
  g.addNode(0, CPose3D());
  g.addNode(1, P1);
  ASSERT_TRUE(g.addEdge(0, 1, T01));
  g.fix(1);
  g.optimize(50);
  EXPECT_LT(poseDistance(g.pose(0), P1 + (-T01)), 1e-6);
}

TEST(PoseGraph, EdgeFromNodesHasZeroError) {
  PoseGraph g;
  g.addNode(3, CPose3D(0, 0, 0, 0.1, 0, 0));
  g.addNode(7, CPose3D(1, 2, 3, 0.5, 0.2, -0.3));
  ASSERT_TRUE(g.addEdgeFromNodes(3, 7));
  EXPECT_LT(g.squaredError(), 1e-20);
}

TEST(PoseGraph, RefusesDuplicatesSelfEdgesAndMissingNodes) {
  PoseGraph g;
  g.addNode(0, CPose3D());
  g.addNode(1, CPose3D(1, 0, 0, 0, 0, 0));
  EXPECT_TRUE(g.addEdge(0, 1, CPose3D(1, 0, 0, 0, 0, 0)));
  EXPECT_FALSE(g.addEdge(0, 1, CPose3D()));
  EXPECT_FALSE(g.addEdge(1, 0, CPose3D()));  // same pair, other direction
  EXPECT_FALSE(g.addEdge(1, 1, CPose3D()));
  EXPECT_FALSE(g.addEdge(0, 5, CPose3D()));
  EXPECT_EQ(g.edgeCount(), 1u);
  EXPECT_TRUE(g.hasEdge(1, 0));
}

// A square of four unit steps with a loop edge that disagrees by 0.2 m: the
// fixed node stays, the error is shared (not dumped on one edge).
TEST(PoseGraph, LoopErrorIsSpreadOverTheCycle) {
  PoseGraph g;
  const CPose3D step(1, 0, 0, M_PI / 2, 0, 0);
  CPose3D p;
  for (int i = 0; i < 4; ++i) {
    g.addNode(i, p);
    p = p + step;
  }
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(g.addEdge(i, i + 1, step));
  ASSERT_TRUE(g.addEdge(3, 0, CPose3D(1.2, 0, 0, M_PI / 2, 0, 0)));
  g.fix(0);
  const double before = g.squaredError();
  const auto r = g.optimize(50);
  EXPECT_NEAR(before, 0.04, 1e-9);
  EXPECT_LT(r.final_sq_error, 0.5 * before);
  EXPECT_GT(r.iterations, 0);
  EXPECT_LT(poseDistance(g.pose(0), CPose3D()), 1e-12);
}

// max_iterations reaches MRPT (its yaml parameter, read as size_t).
TEST(PoseGraph, IterationLimitIsPassedOn) {
  auto square = [] {
    PoseGraph g;
    const CPose3D step(1, 0, 0, M_PI / 2, 0, 0);
    CPose3D p;
    for (int i = 0; i < 4; ++i) {
      g.addNode(i, p + CPose3D(0.1 * i, 0, 0.05 * i, 0.1 * i, 0, 0));
      p = p + step;
    }
    for (int i = 0; i < 3; ++i) g.addEdge(i, i + 1, step);
    g.addEdge(3, 0, step);
    g.fix(0);
    return g;
  };
  PoseGraph a = square(), b = square();
  const auto ra = a.optimize(1), rb = b.optimize(100);
  EXPECT_LE(ra.iterations, 1);
  EXPECT_GT(rb.iterations, ra.iterations);
  EXPECT_LT(rb.final_sq_error, 1e-10);
}

TEST(PoseGraph, NothingToOptimiseIsATrivialSuccess) {
  PoseGraph g;
  g.addNode(0, CPose3D());
  g.fix(0);
  const auto r = g.optimize();
  EXPECT_TRUE(r.ok);
  EXPECT_EQ(r.iterations, 0);
}
