// Cost of the ORB vocabulary (lib/place):
//   - training with the shipped recipe (configs/orb_vocab.md): ORB extraction
//     and k-medians training timed separately;
//   - loading the shipped file, and a 1M-word vocabulary (k = 10, L = 6, a
//     complete tree of random centres: loading cost depends on the size only),
//     median of 5 loads each, from the page cache;
//   - transform (descriptors -> BoW + feature vector) per fr1_rpy frame.
//
//   bench_vocab [SHARED_DIR] [--no-train]
//
// SHARED_DIR defaults to ../shared next to the repository. Times are wall
// clock plus process CPU time (meaningful on a shared machine).
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "core/timing.h"
#include "place/orb_vocabulary.h"
#include "place/training_images.h"
#include "place/vocabulary_trainer.h"

using namespace dynslam;
namespace fs = std::filesystem;

namespace {

struct Timing {
  double wall_ms, cpu_ms;
};

Timing timeIt(const std::function<void()>& fn) {
  const double c0 = dynslam::processCpuMs();
  const auto t0 = SteadyClock::now();
  fn();
  return {msSince(t0), processCpuMs() - c0};
}

/// Median wall (and its cpu) over n runs.
Timing medianOf(int n, const std::function<void()>& fn) {
  std::vector<Timing> v;
  for (int i = 0; i < n; ++i) v.push_back(timeIt(fn));
  std::sort(v.begin(), v.end(),
            [](const Timing& a, const Timing& b) { return a.wall_ms < b.wall_ms; });
  return v[v.size() / 2];
}

/// Complete k-ary tree of depth L with random centres and IDF weights.
OrbVocabulary randomCompleteVocabulary(int k, int levels) {
  VocabularyTree t;
  t.k = k;
  t.levels = levels;
  std::size_t width = 1;
  std::mt19937_64 rng(7);
  for (int d = 0; d <= levels; ++d, width *= static_cast<std::size_t>(k))
    for (std::size_t i = 0; i < width; ++i) {
      t.centres.push_back({rng(), rng(), rng(), rng()});
      t.child_count.push_back(d < levels ? static_cast<uint8_t>(k) : 0);
      if (d == levels) t.idf.push_back(static_cast<float>(rng() % 5000) / 1000.f);
    }
  return OrbVocabulary(std::move(t));
}

void printLoad(const char* name, const std::string& path) {
  std::size_t words = 0;
  const Timing t = medianOf(5, [&] { words = OrbVocabulary::load(path).words(); });
  std::printf("load %-22s %8zu words  %7.2f MB  median of 5: %7.1f ms wall, %7.1f ms cpu\n", name,
              words, static_cast<double>(fs::file_size(path)) / 1e6, t.wall_ms, t.cpu_ms);
}

void printTransform(const char* name, const OrbVocabulary& voc,
                    const std::vector<cv::Mat>& frames) {
  std::vector<double> ms;
  BowVector bow;
  FeatureVector fv;
  std::size_t n_words = 0;
  for (const cv::Mat& d : frames) {
    ms.push_back(timeIt([&] { voc.transform(d, bow, fv, std::min(2, voc.levels())); }).wall_ms);
    n_words += bow.size();
  }
  std::sort(ms.begin(), ms.end());
  std::printf("transform %-17s median %.3f ms, p95 %.3f ms per frame (%.0f words/frame)\n", name,
              ms[ms.size() / 2], ms[ms.size() * 95 / 100],
              static_cast<double>(n_words) / frames.size());
}

}  // namespace

int main(int argc, char** argv) {
  std::string shared =
      fs::weakly_canonical(fs::path(DYNSLAM_SOURCE_DIR) / ".." / "shared").string();
  bool train = true;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--no-train") == 0)
      train = false;
    else
      shared = argv[i];
  }
  const std::string rpy = shared + "/data/tum/rgbd_dataset_freiburg1_rpy";
  const std::string shipped = std::string(DYNSLAM_SOURCE_DIR) + "/configs/orb_vocab_k10_L5.bin";
  const fs::path tmp = fs::temp_directory_path() / ("bench_vocab_" + std::to_string(::getpid()));
  fs::create_directories(tmp);

  if (train) {
    // The recipe of configs/orb_vocab.md, inputs in the same order (the
    // shell expands people/*.jpg sorted), so the result must equal the file.
    std::vector<std::string> inputs{rpy};
    for (const char* p :
         {"000000000785.jpg", "000000040083.jpg", "000000196141.jpg", "000000197388.jpg", "bus.jpg",
          "ochuman_003799.jpg", "ochuman_003896.jpg", "zidane.jpg", "basketball1.png"})
      inputs.push_back(shared + "/data/people/" + p);
    const std::vector<std::string> images = listTrainingImages(inputs, 4);
    std::vector<cv::Mat> desc;
    const Timing te = timeIt([&] { desc = extractTrainingDescriptors(images, OrbParams{}); });
    std::size_t n = 0;
    for (const cv::Mat& d : desc) n += static_cast<std::size_t>(d.rows);
    OrbVocabulary voc;
    const Timing tt = timeIt([&] { voc = trainVocabulary(desc, VocabularyParams{}); });
    voc.save((tmp / "recipe.bin").string());
    std::printf("shipped recipe: %zu images, %zu descriptors -> %zu words (%zu nodes), %.2f MB\n",
                images.size(), n, voc.words(), voc.nodes(),
                static_cast<double>(fs::file_size(tmp / "recipe.bin")) / 1e6);
    std::printf("  ORB extraction %.1f s wall (%.1f s cpu), training %.1f s wall (%.1f s cpu)\n",
                te.wall_ms / 1e3, te.cpu_ms / 1e3, tt.wall_ms / 1e3, tt.cpu_ms / 1e3);
    const VocabularyTree& a = voc.tree();
    const OrbVocabulary shipped_voc = OrbVocabulary::load(shipped);
    const VocabularyTree& b = shipped_voc.tree();
    std::printf("  same tree as %s: %s\n", shipped.c_str(),
                a.centres == b.centres && a.child_count == b.child_count && a.idf == b.idf
                    ? "yes"
                    : "NO (the shipped file is stale: retrain it with configs/orb_vocab.md)");
  }

  const std::string big = (tmp / "k10_L6.bin").string();
  randomCompleteVocabulary(10, 6).save(big);
  printLoad("shipped k10 L5", shipped);
  printLoad("complete k10 L6", big);

  std::vector<std::string> frames = listTrainingImages({rpy}, 7);
  frames.resize(std::min<std::size_t>(frames.size(), 60));
  const std::vector<cv::Mat> desc = extractTrainingDescriptors(frames, OrbParams{});
  printTransform("shipped k10 L5", OrbVocabulary::load(shipped), desc);
  printTransform("complete k10 L6", OrbVocabulary::load(big), desc);
  fs::remove_all(tmp);
  return 0;
}
