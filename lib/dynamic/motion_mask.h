#pragma once
// Mask building of the motion check: the moving points grown into their
// objects over depth (DepthRegionGrower), each region kept only if enough of
// its tracked points moved (the vote), and cut back to the pixels nearer to a
// moving point than to a static one and within max_seed_distance_px of a
// moving point (regions leak into furniture, desks and walls a person
// touches). Runs on a grid mask_downsample times coarser than the image.
#include <opencv2/core.hpp>

#include <cstdint>
#include <vector>

#include "dynamic/depth_masks.h"
#include "dynamic/motion_check_params.h"

namespace dynslam {

/// CV_8U evidence image of image_size (0 = static; else the region's share of
/// moving tracks over region_min_dynamic_ratio, as measurePixel). seeds: where regions grow from
/// (raw pixels; limits[k], if not empty, bounds seed k's region: its box);
/// raw_cur / moving: every tracked point of the frame (raw pixels) and
/// whether it moved (or was carried), for the vote and the cut. cur_depth:
/// CV_16UC1 raw units, depth_scale per metre. grower keeps its buffers.
cv::Mat growMotionMask(DepthRegionGrower& grower, const MotionCheckParams& params,
                       const cv::Mat& cur_depth, double depth_scale, cv::Size image_size,
                       std::vector<cv::Point2f> seeds, std::vector<cv::Rect> limits,
                       const std::vector<cv::Point2f>& raw_cur, const std::vector<uint8_t>& moving);

}  // namespace dynslam
