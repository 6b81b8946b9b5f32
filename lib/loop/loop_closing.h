#pragma once
// Place recognition and loop closing, fed by the local mapper. Every mapped
// keyframe is described as a bag of words and indexed; relocalisation asks the
// index for keyframes that look like the lost frame. Each newly mapped
// keyframe is compared with the non-covisible part of the map: a
// candidate place seen by three consecutive keyframes is verified by a rigid
// alignment of matched map points (RigidAligner), and the loop is closed by
// LoopCorrector (fusion and essential-graph optimisation on MRPT graph-SLAM),
// optionally followed by a global bundle adjustment. All of it runs inside
// the local mapper's step for the keyframe (keyFrameMapped), so a loop is
// closed at a fixed point of the run: the tracker waits for that step.
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include "loop/loop_corrector.h"
#include "loop/rigid_aligner.h"
#include "map/keyframe_interfaces.h"
#include "mapping/local_mapper.h"
#include "optim/bundle_adjuster.h"
#include "place/keyframe_database.h"
#include "place/orb_vocabulary.h"

namespace dynslam::loop {

struct LoopClosingParams {
  bool enabled = true;             ///< place recognition, relocalisation by BoW, loop closing
  std::string vocabulary;          ///< vocabulary file (set by the config loader)
  bool close_loops = true;         ///< false: place recognition for relocalisation only
  int min_map_keyframes = 10;      ///< no loop detection in smaller maps
  int min_keyframes_between = 10;  ///< keyframes between two loop closures
  int consistency = 3;             ///< consecutive keyframes that must see the candidate place
  int max_hamming = 50;            ///< descriptor distance for a loop match
  float ratio = 0.8f;              ///< best / second-best distance ratio
  int min_inliers = 30;            ///< aligned 3D-3D matches a loop needs
  bool global_ba = true;           ///< global bundle adjustment after each closure
  BAParams global_ba_params;
  RigidAlignerParams aligner;
  LoopCorrectorParams corrector;
};

struct LoopClosingStats {
  std::size_t keyframes_indexed = 0, keyframes_checked = 0, candidates = 0, verifications = 0,
              loops_closed = 0, global_bas = 0, relocalisation_queries = 0;
  /// Over all closures: duplicate map points merged into the loop's and
  /// points fused by projection (LoopCorrectionStats).
  std::size_t points_merged = 0, points_fused = 0;
  std::vector<double> detect_ms, correct_ms, global_ba_ms;
  std::vector<std::pair<long, long>> loops;  ///< (current, loop) keyframe ids
};

class LoopClosing : public MappedKeyFrameListener, public RelocalisationCandidateSource {
 public:
  LoopClosing(Map& map, std::shared_ptr<const OrbVocabulary> vocabulary,
              const LoopClosingParams& params);

  void keyFrameMapped(KeyFrame* kf) override;
  void keyFrameCulled(KeyFrame* kf) override;
  std::vector<KeyFrame*> relocalisationCandidates(const FeatureSet& f) override;
  /// Indexes a keyframe of a map read from a file for place recognition
  /// (no loop check: its map was corrected when it was made).
  void indexLoadedKeyFrame(KeyFrame* kf);

  LoopClosingStats stats() const;

 private:
  void process(KeyFrame* kf);
  /// Keyframes of a place seen consistently by consecutive keyframes.
  std::vector<KeyFrame*> consistentCandidates(KeyFrame* kf, const BowVector& bow);
  bool verifyAndClose(KeyFrame* kf, KeyFrame* candidate);
  BowVector describe(const FeatureSet& f) const;

  Map& map_;
  std::shared_ptr<const OrbVocabulary> voc_;
  LoopClosingParams p_;
  KeyFrameDatabase db_;
  LoopCorrector corrector_;

  std::vector<std::pair<std::set<KeyFrame*>, int>>
      groups_;  ///< previous keyframe's candidate groups
  long last_loop_kf_ = -1000000;

  mutable std::mutex stats_mutex_;
  LoopClosingStats stats_;
};

}  // namespace dynslam::loop
