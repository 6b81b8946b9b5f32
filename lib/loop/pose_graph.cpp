#include "loop/pose_graph.h"

#include <mrpt/graphslam/levmarq.h>
#include <mrpt/poses/Lie/SE.h>

#include <algorithm>
#include <stdexcept>

#include "core/timing.h"

namespace dynslam::loop {

void PoseGraph::addNode(Id id, const mrpt::poses::CPose3D& T_w) { g_.nodes[id] = T_w; }

bool PoseGraph::hasEdge(Id i, Id j) const {
  return pairs_.count({std::min(i, j), std::max(i, j)}) > 0;
}

bool PoseGraph::addEdge(Id i, Id j, const mrpt::poses::CPose3D& T_ij) {
  if (i == j || !hasNode(i) || !hasNode(j)) return false;
  if (!pairs_.insert({std::min(i, j), std::max(i, j)}).second) return false;
  g_.insertEdge(i, j, T_ij);
  return true;
}

bool PoseGraph::addEdgeFromNodes(Id i, Id j) {
  if (!hasNode(i) || !hasNode(j)) return false;
  return addEdge(i, j, mrpt::poses::CPose3D(g_.nodes.at(j)) - mrpt::poses::CPose3D(g_.nodes.at(i)));
}

const mrpt::poses::CPose3D& PoseGraph::pose(Id id) const {
  auto it = g_.nodes.find(id);
  if (it == g_.nodes.end()) throw std::out_of_range("PoseGraph::pose: no such node");
  return it->second;
}

double PoseGraph::squaredError() const {
  // The same residual MRPT minimises (levmarq_impl.h).
  double e = 0;
  for (const auto& [ids, T_ij] : g_.edges) {
    const mrpt::poses::CPose3D& Pi = g_.nodes.at(ids.first);
    const mrpt::poses::CPose3D& Pj = g_.nodes.at(ids.second);
    e += mrpt::poses::Lie::SE<3>::log((Pj - Pi) - T_ij).asEigen().squaredNorm();
  }
  return e;
}

PoseGraphResult PoseGraph::optimize(int max_iterations) {
  PoseGraphResult r;
  const auto t0 = SteadyClock::now();
  r.initial_sq_error = r.final_sq_error = squaredError();
  std::set<mrpt::graphs::TNodeID> free;
  for (const auto& [id, p] : g_.nodes)
    if (!fixed_.count(id)) free.insert(id);
  if (fixed_.empty() && !free.empty()) free.erase(free.begin());
  // MRPT asserts a non-empty problem; nothing to move is a trivial success.
  bool has_free_edge = false;
  for (const auto& [ids, e] : g_.edges)
    if (free.count(ids.first) || free.count(ids.second)) has_free_edge = true;
  if (!free.empty() && has_free_edge) {
    g_.root = fixed_.empty() ? g_.nodes.begin()->first : *fixed_.begin();
    mrpt::graphslam::TResultInfoSpaLevMarq info{};
    mrpt::containers::yaml params = mrpt::containers::yaml::Map();
    params["max_iterations"] = static_cast<uint64_t>(std::max(1, max_iterations));
    mrpt::graphslam::optimize_graph_spa_levmarq(g_, info, &free, params);
    r.iterations = static_cast<int>(info.num_iters);
    r.final_sq_error = squaredError();
  }
  r.ok = true;
  r.time_ms = msSince(t0);
  return r;
}

}  // namespace dynslam::loop
