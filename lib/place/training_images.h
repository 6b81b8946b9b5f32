#pragma once
// Where vocabulary training data comes from: any mix of image files, image
// folders and TUM sequence folders, subsampled with a stride (neighbouring
// video frames add little but time), turned into ORB descriptors with the
// same extractor the tracker uses, so that the words fit what SLAM sees.
#include <opencv2/core.hpp>

#include <functional>
#include <string>
#include <vector>

#include "features/orb_extractor.h"

namespace dynslam {

/// Expands inputs into image paths, in order: an image file is taken as is;
/// a TUM sequence folder (one with rgb.txt) gives the images listed there; any
/// other folder gives its image files (.png/.jpg/.jpeg/.bmp/.ppm/.pgm/.tif/
/// .tiff, sorted by name, not recursive). Folders and sequences keep every
/// stride-th image, starting with the first. Throws InputError naming the
/// input when it does not exist or holds no image.
std::vector<std::string> listTrainingImages(const std::vector<std::string>& inputs, int stride);

/// ORB descriptors of each image (read as grayscale), one N x 32 matrix per
/// image. progress(done, total) after each image. Throws InputError naming
/// an image that cannot be read.
std::vector<cv::Mat> extractTrainingDescriptors(
    const std::vector<std::string>& images, const OrbParams& orb,
    const std::function<void(std::size_t, std::size_t)>& progress = {});

}  // namespace dynslam
