#pragma once
// A thin wrapper over MRPT's graph-SLAM (mrpt::graphs::CNetworkOfPoses3D
// optimised by mrpt::graphslam::optimize_graph_spa_levmarq) that fixes the
// conventions once, so that callers never have to remember them:
//
//  * nodes are camera-to-world poses T_wi (CameraPose::wc());
//  * an edge i -> j holds the pose of j seen from i, T_ij = T_wi^-1 T_wj,
//    i.e. MRPT's (P_j (-) P_i); the residual MRPT minimises is
//    log((P_j (-) P_i) (-) T_ij), zero when the nodes agree with the edge;
//  * every edge has identity information (CNetworkOfPoses3D carries no
//    covariance), like the essential graph of ORB-SLAM: the graph only has to
//    spread a loop's correction along the trajectory, and edges between
//    keyframes of one neighbourhood are all about equally reliable;
//  * at most one edge per unordered pair: MRPT keeps one Jacobian per edge
//    but duplicates would simply double the weight of that pair.
#include <mrpt/graphs/CNetworkOfPoses.h>
#include <mrpt/poses/CPose3D.h>

#include <cstdint>
#include <set>
#include <utility>

namespace dynslam::loop {

struct PoseGraphResult {
  bool ok = false;
  int iterations = 0;
  double initial_sq_error = 0;  ///< sum over edges of |log residual|^2
  double final_sq_error = 0;
  double time_ms = 0;
};

class PoseGraph {
 public:
  using Id = std::uint64_t;

  void addNode(Id id, const mrpt::poses::CPose3D& T_w);
  bool hasNode(Id id) const { return g_.nodes.count(id) > 0; }
  /// Adds i -> j with measurement T_ij (pose of j in i's frame). Returns
  /// false (and adds nothing) for a self edge, a missing node or a pair that
  /// already has an edge in either direction.
  bool addEdge(Id i, Id j, const mrpt::poses::CPose3D& T_ij);
  /// The edge measured from the nodes' current poses.
  bool addEdgeFromNodes(Id i, Id j);
  bool hasEdge(Id i, Id j) const;
  /// Fixed nodes keep their pose; if none is fixed, the lowest id is.
  void fix(Id id) { fixed_.insert(id); }

  std::size_t nodeCount() const { return g_.nodes.size(); }
  std::size_t edgeCount() const { return g_.edges.size(); }
  const mrpt::poses::CPose3D& pose(Id id) const;
  double squaredError() const;

  /// Levenberg-Marquardt; thresholds are MRPT's (gradient / step below 1e-6).
  PoseGraphResult optimize(int max_iterations = 20);

  const mrpt::graphs::CNetworkOfPoses3D& graph() const { return g_; }

 private:
  mrpt::graphs::CNetworkOfPoses3D g_;
  std::set<std::pair<Id, Id>> pairs_;  ///< (min, max) of each edge
  std::set<Id> fixed_;
};

}  // namespace dynslam::loop
