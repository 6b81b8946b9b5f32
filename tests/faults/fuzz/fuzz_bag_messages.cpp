// libFuzzer target: the ROS message conversions of rawlog/bag_messages.h, fed
// with bytes deserialised as the messages a bag holds (the first byte picks
// sensor_msgs/Image as RGB or as depth, CompressedImage or CameraInfo). A
// message's sizes, encodings and lengths are data: every input must give a
// result or an InputError, never a crash.
#include <ros/serialization.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>

#include <cstdint>
#include <cstring>
#include <initializer_list>

#include "core/errors.h"
#include "rawlog/bag_messages.h"

namespace {

/// Serialised field kinds, to check the lengths a message's bytes claim
/// before ROS's deserialiser allocates them (it resizes first, then finds
/// the input too short): an allocation of gigabytes is the harness's fault.
enum class Field { kU8, kU32, kTime, kString, kBytes, kF64Array9, kF64Array12, kF64Vector };

const std::initializer_list<Field> kHeader = {Field::kU32, Field::kTime, Field::kString};

bool lengthsFit(const std::uint8_t* data, std::size_t size,
                std::initializer_list<std::initializer_list<Field>> layout) {
  std::size_t at = 0;
  const auto take = [&](std::size_t n) {
    if (n > size - at) return false;
    at += n;
    return true;
  };
  for (const auto& part : layout)
    for (const Field f : part) {
      std::uint32_t len = 0;
      switch (f) {
        case Field::kU8:
          if (!take(1)) return false;
          break;
        case Field::kU32:
          if (!take(4)) return false;
          break;
        case Field::kTime:
          if (!take(8)) return false;
          break;
        case Field::kF64Array9:
          if (!take(72)) return false;
          break;
        case Field::kF64Array12:
          if (!take(96)) return false;
          break;
        case Field::kString:
        case Field::kBytes:
        case Field::kF64Vector:
          if (size - at < 4) return false;
          std::memcpy(&len, data + at, 4);
          at += 4;
          if (!take(f == Field::kF64Vector ? std::size_t(len) * 8 : len)) return false;
          break;
      }
    }
  return true;
}

template <class Msg>
Msg deserialise(const std::uint8_t* data, std::size_t size) {
  Msg m;
  ros::serialization::IStream in(const_cast<std::uint8_t*>(data), static_cast<std::uint32_t>(size));
  ros::serialization::deserialize(in, m);
  return m;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using dynslam::InputError;
  if (size < 1) return 0;
  const std::uint8_t kind = data[0] % 4;
  ++data;
  --size;
  try {
    if (kind <= 1) {
      if (!lengthsFit(
              data, size,
              {kHeader,
               {Field::kU32, Field::kU32, Field::kString, Field::kU8, Field::kU32, Field::kBytes}}))
        return 0;
      const auto image = deserialise<sensor_msgs::Image>(data, size);
      if (kind == 0) {
        dynslam::bgrFromImage(image, "fuzz");
      } else {
        dynslam::DepthRange range;
        const std::string e = dynslam::depthEncoding(image.encoding);
        dynslam::depthFromImage(image, dynslam::depthUnitsPerMetre(e), "fuzz", &range);
      }
    } else if (kind == 2) {
      if (!lengthsFit(data, size, {kHeader, {Field::kString, Field::kBytes}})) return 0;
      dynslam::bgrFromCompressed(deserialise<sensor_msgs::CompressedImage>(data, size), "fuzz");
    } else {
      if (!lengthsFit(
              data, size,
              {kHeader,
               {Field::kU32, Field::kU32, Field::kString, Field::kF64Vector, Field::kF64Array9,
                Field::kF64Array9, Field::kF64Array12, Field::kU32, Field::kU32, Field::kU32,
                Field::kU32, Field::kU32, Field::kU32, Field::kU8}}))
        return 0;
      dynslam::cameraFromInfo(deserialise<sensor_msgs::CameraInfo>(data, size), "fuzz", "fuzz");
    }
  } catch (const InputError&) {
  }
  return 0;
}
