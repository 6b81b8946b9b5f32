#pragma once
// A 256-bit ORB descriptor as four 64-bit words: the vocabulary compares
// millions of them, and word-wise XOR + popcount is several times faster than
// byte loops over cv::Mat rows.
#include <opencv2/core.hpp>

#include <array>
#include <cstdint>
#include <cstring>
#include <vector>

namespace dynslam {

using BinaryDescriptor = std::array<uint64_t, 4>;
static_assert(sizeof(BinaryDescriptor) == 32, "ORB descriptors are 32 bytes");

inline int hammingDistance(const BinaryDescriptor& a, const BinaryDescriptor& b) {
  return __builtin_popcountll(a[0] ^ b[0]) + __builtin_popcountll(a[1] ^ b[1]) +
         __builtin_popcountll(a[2] ^ b[2]) + __builtin_popcountll(a[3] ^ b[3]);
}

inline BinaryDescriptor toBinaryDescriptor(const uint8_t* row) {
  BinaryDescriptor d;
  std::memcpy(d.data(), row, sizeof d);
  return d;
}

/// Rows of an N x 32 CV_8UC1 matrix; throws std::invalid_argument otherwise.
std::vector<BinaryDescriptor> toBinaryDescriptors(const cv::Mat& descriptors);

}  // namespace dynslam
