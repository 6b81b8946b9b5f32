#pragma once
// Which keyframes might show the place the camera sees now: an inverted
// index word -> keyframes, so a query only scores keyframes sharing words
// with it. Candidates are then ranked per covisibility group (a place seen
// by several connected keyframes beats a single lucky match), as in
// ORB-SLAM's relocalisation and loop detection.
//
// Thread-safe: the tracker (relocalisation), the local mapper (add/erase)
// and the loop closer may call it concurrently. Queries also read the
// keyframes' `bad` flag and covisibility lists, which lib/map must keep
// consistent under concurrent use.
#include <mutex>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "map/keyframe.h"
#include "place/bow_vector.h"

namespace dynslam {

struct PlaceCandidate {
  KeyFrame* kf = nullptr;
  float score = 0;        ///< l1Score(query, kf)
  float group_score = 0;  ///< sum of the scores in kf's covisibility group
};

class KeyFrameDatabase {
 public:
  /// n_words: size of the vocabulary the BoW vectors come from.
  explicit KeyFrameDatabase(std::size_t n_words);

  /// Indexes kf under the words of bow (kept for scoring); replaces a
  /// previous entry of kf. Throws std::invalid_argument on a word id
  /// outside the vocabulary.
  void add(KeyFrame* kf, BowVector bow);
  /// No-op for a keyframe that is not indexed.
  void erase(const KeyFrame* kf);
  void clear();
  std::size_t size() const;
  /// Copies kf's indexed BoW vector into bow; false if kf is not indexed.
  bool bowOf(const KeyFrame* kf, BowVector& bow) const;

  /// Keyframes that may show the place of a lost frame, best first: every
  /// keyframe sharing at least 80% of the best count of shared words is
  /// scored; each accumulates the scores of its 10 best covisible keyframes
  /// that were scored too; the best keyframe of every group scoring at least
  /// 75% of the best group is returned. Bad keyframes are skipped.
  std::vector<PlaceCandidate> detectRelocalisationCandidates(const BowVector& bow) const;

  /// The same for a new keyframe `query`, leaving out query itself and its
  /// covisible keyframes (those are not loops), and keyframes scoring below
  /// min_score (typically the lowest score of query against its covisibles).
  std::vector<PlaceCandidate> detectLoopCandidates(const KeyFrame* query, const BowVector& bow,
                                                   float min_score) const;

 private:
  void eraseLocked(const KeyFrame* kf);
  std::vector<PlaceCandidate> detect(const BowVector& bow,
                                     const std::unordered_set<const KeyFrame*>& excluded,
                                     float min_score) const;

  mutable std::mutex mutex_;
  std::vector<std::vector<KeyFrame*>> inverted_;  ///< word -> keyframes
  std::unordered_map<const KeyFrame*, BowVector> bows_;
};

}  // namespace dynslam
