#include "place/keyframe_database.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace dynslam {

namespace {
constexpr float kMinCommonWordsRatio = 0.8f;  ///< of the best count of shared words
constexpr std::size_t kGroupSize = 10;        ///< covisibles accumulated per candidate
constexpr float kMinGroupScoreRatio = 0.75f;  ///< of the best group score
}  // namespace

KeyFrameDatabase::KeyFrameDatabase(std::size_t n_words) : inverted_(n_words) {}

void KeyFrameDatabase::add(KeyFrame* kf, BowVector bow) {
  for (const BowEntry& e : bow)
    if (e.word >= inverted_.size())
      throw std::invalid_argument("keyframe " + std::to_string(kf->id) + ": word " +
                                  std::to_string(e.word) + " is outside the vocabulary (" +
                                  std::to_string(inverted_.size()) + " words)");
  std::lock_guard<std::mutex> lock(mutex_);
  eraseLocked(kf);
  for (const BowEntry& e : bow) inverted_[e.word].push_back(kf);
  bows_[kf] = std::move(bow);
}

void KeyFrameDatabase::erase(const KeyFrame* kf) {
  std::lock_guard<std::mutex> lock(mutex_);
  eraseLocked(kf);
}

void KeyFrameDatabase::eraseLocked(const KeyFrame* kf) {
  const auto it = bows_.find(kf);
  if (it == bows_.end()) return;
  for (const BowEntry& e : it->second) {
    auto& list = inverted_[e.word];
    list.erase(std::find(list.begin(), list.end(), kf));
  }
  bows_.erase(it);
}

void KeyFrameDatabase::clear() {
  std::lock_guard<std::mutex> lock(mutex_);
  for (auto& list : inverted_) list.clear();
  bows_.clear();
}

std::size_t KeyFrameDatabase::size() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return bows_.size();
}

bool KeyFrameDatabase::bowOf(const KeyFrame* kf, BowVector& bow) const {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto it = bows_.find(kf);
  if (it == bows_.end()) return false;
  bow = it->second;
  return true;
}

std::vector<PlaceCandidate> KeyFrameDatabase::detectRelocalisationCandidates(
    const BowVector& bow) const {
  return detect(bow, {}, 0.f);
}

std::vector<PlaceCandidate> KeyFrameDatabase::detectLoopCandidates(const KeyFrame* query,
                                                                   const BowVector& bow,
                                                                   float min_score) const {
  std::unordered_set<const KeyFrame*> excluded{query};
  for (const KeyFrame* kf : query->orderedCovisibles()) excluded.insert(kf);
  return detect(bow, excluded, min_score);
}

std::vector<PlaceCandidate> KeyFrameDatabase::detect(
    const BowVector& bow, const std::unordered_set<const KeyFrame*>& excluded,
    float min_score) const {
  std::lock_guard<std::mutex> lock(mutex_);
  struct Shared {
    int words = 0;
    float score = -1;  ///< < 0: not scored
  };
  std::unordered_map<KeyFrame*, Shared> shared;
  for (const BowEntry& e : bow) {
    if (e.word >= inverted_.size()) continue;
    for (KeyFrame* kf : inverted_[e.word])
      if (!kf->bad && !excluded.count(kf)) ++shared[kf].words;
  }
  int max_words = 0;
  for (const auto& [kf, s] : shared) max_words = std::max(max_words, s.words);
  const float min_words = kMinCommonWordsRatio * static_cast<float>(max_words);

  std::vector<KeyFrame*> scored;
  for (auto& [kf, s] : shared) {
    if (static_cast<float>(s.words) < min_words) continue;
    const auto score = static_cast<float>(l1Score(bow, bows_.at(kf)));
    if (score < min_score) continue;
    s.score = score;
    scored.push_back(kf);
  }
  // Id order: the result must not depend on pointer values.
  std::sort(scored.begin(), scored.end(),
            [](const KeyFrame* a, const KeyFrame* b) { return a->id < b->id; });

  std::vector<PlaceCandidate> groups;
  float best_group = 0;
  for (KeyFrame* kf : scored) {
    PlaceCandidate g{kf, shared[kf].score, shared[kf].score};
    for (KeyFrame* n : kf->bestCovisibles(kGroupSize)) {
      const auto it = shared.find(n);
      if (it == shared.end() || it->second.score < 0) continue;
      g.group_score += it->second.score;
      if (it->second.score > g.score) {
        g.kf = n;
        g.score = it->second.score;
      }
    }
    best_group = std::max(best_group, g.group_score);
    groups.push_back(g);
  }
  std::sort(groups.begin(), groups.end(), [](const PlaceCandidate& a, const PlaceCandidate& b) {
    return a.group_score != b.group_score ? a.group_score > b.group_score : a.kf->id < b.kf->id;
  });
  std::vector<PlaceCandidate> out;
  std::unordered_set<const KeyFrame*> taken;
  for (const PlaceCandidate& g : groups)
    if (g.group_score >= kMinGroupScoreRatio * best_group && taken.insert(g.kf).second)
      out.push_back(g);
  return out;
}

}  // namespace dynslam
