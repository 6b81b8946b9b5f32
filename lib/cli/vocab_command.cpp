// `dynslam vocab train INPUT... -o OUT.bin` and `dynslam vocab info FILE`:
// argument layer over lib/place (training data, k-medians training, file
// format). The training command line is stored in the file as its note, so
// `vocab info` says how any vocabulary was made.
#include <mrpt/3rdparty/tclap/CmdLine.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "cli/commands.h"
#include "core/atomic_file.h"
#include "core/progress.h"
#include "core/timing.h"
#include "place/orb_vocabulary.h"
#include "place/training_images.h"
#include "place/vocabulary_trainer.h"

namespace dynslam::cli {
namespace {

constexpr const char* kUsageText =
    "usage: dynslam vocab train INPUT... -o OUT.bin [--k 10] [--levels 5] [--stride N]\n"
    "                           [--max-features 1000] [--iterations 10] [--seed 1]\n"
    "       dynslam vocab info FILE\n"
    "       dynslam vocab (train|info) --help\n";

/// Fails before minutes of training, not after.
void checkOutputFolder(const std::string& out) {
  std::string dir = std::filesystem::path(out).parent_path().string();
  if (dir.empty()) dir = ".";
  if (!isDirectory(dir)) throw std::runtime_error(out + ": folder '" + dir + "' does not exist");
  if (::access(dir.c_str(), W_OK) != 0)
    throw std::runtime_error(out + ": folder '" + dir + "' is not writable");
}

template <typename T>
bool inRange(TCLAP::ValueArg<T>& arg, T lo, T hi, const char* prog) {
  if (arg.getValue() >= lo && arg.getValue() <= hi) return true;
  std::fprintf(stderr, "%s: error: --%s must be in %s..%s\n", prog, arg.getName().c_str(),
               std::to_string(lo).c_str(), std::to_string(hi).c_str());
  return false;
}

int trainMain(int argc, char** argv) {
  TCLAP::CmdLine cmd(
      "Trains an ORB vocabulary (hierarchical k-medians over the descriptors of the tracker's "
      "ORB extractor, IDF weights from the training images) for relocalisation and loop "
      "detection. INPUTs are image files, folders of images or TUM sequence folders (the "
      "images listed in rgb.txt); folders and sequences are subsampled with --stride.",
      ' ', DYNSLAM_VERSION);
  TCLAP::UnlabeledMultiArg<std::string> inputs_arg(
      "inputs", "image files, image folders or TUM sequence folders", true, "INPUT", cmd);
  TCLAP::ValueArg<std::string> out_arg("o", "output", "vocabulary file to write", true, "",
                                       "OUT.bin", cmd);
  TCLAP::ValueArg<int> k_arg("", "k", "branching factor (2..255)", false, 10, "K", cmd);
  TCLAP::ValueArg<int> levels_arg("", "levels", "tree depth L: up to k^L words (1..16)", false, 5,
                                  "L", cmd);
  TCLAP::ValueArg<int> stride_arg("", "stride", "use every N-th image of each folder or sequence",
                                  false, 1, "N", cmd);
  TCLAP::ValueArg<int> features_arg("", "max-features", "ORB keypoints per image", false, 1000, "N",
                                    cmd);
  TCLAP::ValueArg<int> iterations_arg("", "iterations", "max k-medians iterations per node", false,
                                      10, "N", cmd);
  TCLAP::ValueArg<uint64_t> seed_arg("", "seed", "random seed (same seed, same vocabulary)", false,
                                     1, "SEED", cmd);
  int exit_code = kOk;
  if (!parseArguments(cmd, argc, argv, exit_code)) return exit_code;
  if (!inRange(k_arg, 2, 255, argv[0]) || !inRange(levels_arg, 1, 16, argv[0]) ||
      !inRange(stride_arg, 1, 1 << 30, argv[0]) || !inRange(features_arg, 1, 1 << 20, argv[0]) ||
      !inRange(iterations_arg, 1, 1000, argv[0]))
    return kUsage;

  const std::string out = out_arg.getValue();
  checkOutputFolder(out);
  const std::vector<std::string> images =
      listTrainingImages(inputs_arg.getValue(), stride_arg.getValue());

  auto t0 = SteadyClock::now();
  OrbParams orb;
  orb.n_features = features_arg.getValue();
  ProgressLine extract_progress("extracting ORB, image", images.size());
  const std::vector<cv::Mat> descriptors = extractTrainingDescriptors(
      images, orb, [&](std::size_t done, std::size_t) { extract_progress.update(done); });
  extract_progress.finish();
  const double extract_s = secondsSince(t0);
  std::size_t n_descriptors = 0;
  for (const cv::Mat& d : descriptors) n_descriptors += static_cast<std::size_t>(d.rows);

  VocabularyParams params;
  params.k = k_arg.getValue();
  params.levels = levels_arg.getValue();
  params.iterations = iterations_arg.getValue();
  params.seed = seed_arg.getValue();
  std::string note = "dynslam vocab train";
  for (int i = 1; i < argc; ++i) note += std::string(" ") + argv[i];
  t0 = SteadyClock::now();
  ProgressLine train_progress("training, descriptors placed", n_descriptors);
  const OrbVocabulary voc =
      trainVocabulary(descriptors, params, note,
                      [&](std::size_t done, std::size_t) { train_progress.update(done); });
  train_progress.finish();
  const double train_s = secondsSince(t0);
  voc.save(out);
  std::printf(
      "%s: k=%d L=%d, %zu words (%zu nodes) from %zu descriptors of %zu images; "
      "ORB extraction %.1f s, training %.1f s\n",
      out.c_str(), voc.branching(), voc.levels(), voc.words(), voc.nodes(), n_descriptors,
      images.size(), extract_s, train_s);
  return kOk;
}

int infoMain(int argc, char** argv) {
  TCLAP::CmdLine cmd("Prints the shape of an ORB vocabulary file and how long it takes to load.",
                     ' ', DYNSLAM_VERSION);
  TCLAP::UnlabeledValueArg<std::string> file_arg("file", "vocabulary file", true, "", "FILE", cmd);
  int exit_code = kOk;
  if (!parseArguments(cmd, argc, argv, exit_code)) return exit_code;
  const std::string path = file_arg.getValue();
  const auto t0 = SteadyClock::now();
  const OrbVocabulary voc = OrbVocabulary::load(path);
  const double load_ms = secondsSince(t0) * 1e3;
  std::printf(
      "%s\n  branching k   %d\n  levels L      %d\n  nodes         %zu\n"
      "  words         %zu\n  file size     %.2f MB\n  load time     %.1f ms\n"
      "  recipe        %s\n",
      path.c_str(), voc.branching(), voc.levels(), voc.nodes(), voc.words(),
      static_cast<double>(std::filesystem::file_size(path)) / 1e6, load_ms,
      voc.note().empty() ? "(none recorded)" : voc.note().c_str());
  return kOk;
}

}  // namespace

int vocabMain(int argc, char** argv) {
  const std::string action = argc > 1 ? argv[1] : "";
  if (action == "--help" || action == "-h") {
    std::fputs(kUsageText, stdout);
    return kOk;
  }
  int (*sub)(int, char**) = action == "train" ? trainMain : action == "info" ? infoMain : nullptr;
  if (!sub) {
    if (action.empty())
      std::fprintf(stderr, "%s: error: missing action (train or info)\n", argv[0]);
    else
      std::fprintf(stderr, "%s: error: unknown action '%s'\n", argv[0], action.c_str());
    std::fputs(kUsageText, stderr);
    return kUsage;
  }
  std::string prog = std::string(argv[0]) + " " + action;
  std::vector<char*> args{prog.data()};
  for (int i = 2; i < argc; ++i) args.push_back(argv[i]);
  return sub(static_cast<int>(args.size()), args.data());
}

}  // namespace dynslam::cli
