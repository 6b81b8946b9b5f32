// The shipped vocabulary on fr1_rpy frames it was not trained on (the recipe
// uses every 4th frame; these are not multiples of 4), and the training-input
// listing.
#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "core/errors.h"
#include "place/training_images.h"
#include "place_fixtures.h"
#include "testing/test_support.h"

using namespace dynslam;

TEST(ShippedVocabulary, HasTheDocumentedShape) {
  const OrbVocabulary& voc = test::shippedVocabulary();
  EXPECT_EQ(voc.branching(), 10);
  EXPECT_EQ(voc.levels(), 5);
  EXPECT_GT(voc.words(), 10000u);
  EXPECT_NE(voc.note().find("dynslam vocab train"), std::string::npos) << voc.note();
}

TEST(ShippedVocabulary, FrameScoresHighestAgainstItselfThenItsNeighbour) {
  const OrbVocabulary& voc = test::shippedVocabulary();
  for (int f : {101, 302, 503}) {
    const BowVector q = voc.transform(test::rpyDescriptors(f));
    ASSERT_GT(q.size(), 200u) << "frame " << f;
    EXPECT_NEAR(l1Score(q, q), 1.0, 1e-5);
    const double near = l1Score(q, voc.transform(test::rpyDescriptors(f + 1)));
    SCOPED_TRACE("frame " + std::to_string(f) + ", neighbour score " + std::to_string(near));
    EXPECT_LT(near, 1.0);
    for (int far : {f + 150, f + 200 > 690 ? f - 250 : f + 200}) {
      const double s = l1Score(q, voc.transform(test::rpyDescriptors(far)));
      EXPECT_GT(near, s + 0.05) << "far frame " << far;
    }
  }
}

TEST(TrainingImages, TumSequenceIsReadFromRgbTxtWithStride) {
  const auto all = listTrainingImages({test::rpyDir()}, 1);
  const auto strided = listTrainingImages({test::rpyDir()}, 100);
  ASSERT_EQ(all.size(), 723u);  // fr1_rpy rgb.txt entries
  ASSERT_EQ(strided.size(), 8u);
  EXPECT_EQ(strided[0], test::rpyDir() + "/rgb/1305031229.528748.jpg");
  EXPECT_EQ(strided[1], all[100]);
}

TEST(TrainingImages, FoldersGiveTheirImagesSortedAndFilesAreKept) {
  test::TempDir d;
  const cv::Mat img(40, 40, CV_8UC1, cv::Scalar(128));
  cv::imwrite(d / "b.png", img);
  cv::imwrite(d / "a.JPG", img);
  test::writeText(d / "notes.txt", "not an image");
  const auto v = listTrainingImages({d.path(), d / "notes.txt"}, 1);
  EXPECT_EQ(v, (std::vector<std::string>{d / "a.JPG", d / "b.png", d / "notes.txt"}));
  // The text file is only rejected when read.
  try {
    extractTrainingDescriptors(v, OrbParams{});
    ADD_FAILURE() << "read a text file as an image";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), d / "notes.txt");
  }
}

TEST(TrainingImages, MissingOrEmptyInputsNameThePath) {
  test::TempDir d;
  try {
    listTrainingImages({d / "nope"}, 1);
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), d / "nope");
  }
  try {
    listTrainingImages({d.path()}, 1);
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), d.path());
    EXPECT_NE(std::string(e.what()).find("no images"), std::string::npos);
  }
}
