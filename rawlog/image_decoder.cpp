#include "rawlog/image_decoder.h"

#include <opencv2/imgcodecs.hpp>

#include <csetjmp>
#include <cstring>
#include <functional>

#include <jerror.h>
#include <jpeglib.h>
#include <png.h>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "rawlog/image_checks.h"

namespace dynslam {

namespace {

std::string sizeMessage(unsigned long width, unsigned long height) {
  return "image header claims " + std::to_string(width) + " x " + std::to_string(height) +
         " pixels (at most " + std::to_string(kMaxImageSide) + " per side)";
}

// ---------------------------------------------------------------- JPEG
// libjpeg reports through its error manager: error_exit must not return
// (longjmp back to the decoder), emit_message(-1) is a warning about
// corrupt or missing data, which libjpeg would otherwise print and decode
// past. Both end the decode here.

struct JpegErrors {
  jpeg_error_mgr mgr;
  std::jmp_buf jump;
  char message[JMSG_LENGTH_MAX];
};

[[noreturn]] void jpegFail(j_common_ptr cinfo) {
  auto* e = reinterpret_cast<JpegErrors*>(cinfo->err);
  (*cinfo->err->format_message)(cinfo, e->message);
  std::longjmp(e->jump, 1);
}

void jpegMessage(j_common_ptr cinfo, int level) {
  if (level >= 0) return;  // trace messages
  // A warning: corrupt or missing data, except two header quirks that
  // change no pixel.
  const int code = cinfo->err->msg_code;
  if (code == JWRN_JFIF_MAJOR || code == JWRN_ADOBE_XFORM) return;
  jpegFail(cinfo);
}

/// Decodes into `out` (allocated here); no object with a destructor lives
/// in this frame, so the longjmp of an error skips nothing. Returns false
/// with e.message set on failure, or true with `header_error` set when the
/// header was read and refused.
bool decodeJpegInto(const std::string& bytes, DecodedImage as, cv::Mat& out, JpegErrors& e,
                    std::string& header_error) {
  jpeg_decompress_struct cinfo;
  cinfo.err = jpeg_std_error(&e.mgr);
  e.mgr.error_exit = jpegFail;
  e.mgr.emit_message = jpegMessage;
  if (setjmp(e.jump)) {
    jpeg_destroy_decompress(&cinfo);
    return false;
  }
  jpeg_create_decompress(&cinfo);
  jpeg_mem_src(&cinfo, reinterpret_cast<const unsigned char*>(bytes.data()),
               static_cast<unsigned long>(bytes.size()));
  jpeg_read_header(&cinfo, TRUE);
  if (cinfo.image_width > unsigned(kMaxImageSide) || cinfo.image_height > unsigned(kMaxImageSide)) {
    header_error = sizeMessage(cinfo.image_width, cinfo.image_height);
  } else if (as == DecodedImage::kDepth16) {
    header_error = "depth image must be 16-bit single-channel, found 8-bit " +
                   std::to_string(cinfo.num_components) + "-channel (JPEG)";
  } else if (cinfo.jpeg_color_space == JCS_CMYK || cinfo.jpeg_color_space == JCS_YCCK) {
    header_error = "a CMYK JPEG is not a camera image";
  }
  if (!header_error.empty()) {
    jpeg_destroy_decompress(&cinfo);
    return true;
  }
  // As OpenCV asks libjpeg-turbo: BGR straight from the decoder, or the
  // luminance alone for grey.
  cinfo.out_color_space = as == DecodedImage::kGray8 ? JCS_GRAYSCALE : JCS_EXT_BGR;
  jpeg_start_decompress(&cinfo);
  out.create(int(cinfo.output_height), int(cinfo.output_width), CV_8UC(cinfo.output_components));
  while (cinfo.output_scanline < cinfo.output_height) {
    JSAMPROW row = out.ptr<unsigned char>(int(cinfo.output_scanline));
    jpeg_read_scanlines(&cinfo, &row, 1);
  }
  jpeg_finish_decompress(&cinfo);
  jpeg_destroy_decompress(&cinfo);
  return true;
}

cv::Mat decodeJpeg(const std::string& path, const std::string& bytes, DecodedImage as) {
  JpegErrors e{};
  cv::Mat out;
  std::string header_error;
  if (!decodeJpegInto(bytes, as, out, e, header_error))
    throw InputError(path, std::string("cannot decode JPEG (libjpeg: ") + e.message + ")");
  if (!header_error.empty()) throw InputError(path, header_error);
  return out;
}

// ---------------------------------------------------------------- PNG
// libpng calls the error function (which must not return: longjmp through
// png_jmpbuf) on corrupt or missing data (CRC of a critical chunk, zlib
// data, a file cut short), and the warning function on lesser faults of
// ancillary chunks, which it then skips: those are dropped in silence.

struct PngInput {
  const std::string* bytes = nullptr;
  std::size_t at = 0;
  std::string message;
};

[[noreturn]] void pngFail(png_structp png, png_const_charp message) {
  auto* in = static_cast<PngInput*>(png_get_error_ptr(png));
  in->message = message ? message : "unknown libpng error";
  png_longjmp(png, 1);
}

void pngWarn(png_structp, png_const_charp) {}

void pngRead(png_structp png, png_bytep data, png_size_t length) {
  auto* in = static_cast<PngInput*>(png_get_io_ptr(png));
  if (in->bytes->size() - in->at < length) png_error(png, "file cut short");
  std::memcpy(data, in->bytes->data() + in->at, length);
  in->at += length;
}

/// As decodeJpegInto: no object with a destructor in this frame.
bool decodePngInto(PngInput& in, DecodedImage as, cv::Mat& out, std::string& header_error) {
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &in, pngFail, pngWarn);
  if (png == nullptr) {
    in.message = "cannot start libpng";
    return false;
  }
  png_infop info = png_create_info_struct(png);
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    return false;
  }
  if (info == nullptr) png_error(png, "cannot start libpng");
  png_set_read_fn(png, &in, pngRead);
  png_read_info(png, info);
  const png_uint_32 width = png_get_image_width(png, info);
  const png_uint_32 height = png_get_image_height(png, info);
  const int bit_depth = png_get_bit_depth(png, info);
  const int color_type = png_get_color_type(png, info);
  if (width > png_uint_32(kMaxImageSide) || height > png_uint_32(kMaxImageSide)) {
    header_error = sizeMessage(width, height);
  } else if (as == DecodedImage::kDepth16 &&
             (bit_depth != 16 || color_type != PNG_COLOR_TYPE_GRAY)) {
    const int channels = png_get_channels(png, info);
    header_error = "depth image must be 16-bit single-channel, found " + std::to_string(bit_depth) +
                   "-bit " + std::to_string(channels) + "-channel (PNG)";
  }
  if (!header_error.empty()) {
    png_destroy_read_struct(&png, &info, nullptr);
    return true;
  }
  int type = CV_16UC1;
  if (as == DecodedImage::kDepth16) {
    png_set_swap(png);  // PNG stores 16-bit samples big-endian
  } else {
    png_set_expand(png);  // palette -> RGB, grey under 8 bits -> 8, tRNS -> alpha
    png_set_strip_16(png);
    png_set_strip_alpha(png);
    const bool colour = (color_type & PNG_COLOR_MASK_COLOR) != 0;
    if (as == DecodedImage::kGray8) {
      if (colour) png_set_rgb_to_gray(png, 1, 0.299, 0.587);  // cv::imread's weights
      type = CV_8UC1;
    } else {
      if (!colour) png_set_gray_to_rgb(png);
      png_set_bgr(png);
      type = CV_8UC3;
    }
  }
  const int passes = png_set_interlace_handling(png);
  png_read_update_info(png, info);
  out.create(int(height), int(width), type);
  if (png_get_rowbytes(png, info) != out.step[0]) png_error(png, "unexpected row size");
  for (int pass = passes; pass > 0; --pass)
    for (int y = 0; y < out.rows; ++y) png_read_row(png, out.ptr<unsigned char>(y), nullptr);
  png_read_end(png, nullptr);  // the chunks after the image data, up to IEND
  png_destroy_read_struct(&png, &info, nullptr);
  return true;
}

cv::Mat decodePng(const std::string& path, const std::string& bytes, DecodedImage as) {
  PngInput in;
  in.bytes = &bytes;
  cv::Mat out;
  std::string header_error;
  if (!decodePngInto(in, as, out, header_error))
    throw InputError(path, "cannot decode PNG (libpng: " + in.message + ")");
  if (!header_error.empty()) throw InputError(path, header_error);
  return out;
}

/// cv::imread or cv::imdecode, which print nothing a user could act on and
/// return an empty image for data they cannot decode.
cv::Mat decodeOther(const std::string& path, DecodedImage as,
                    const std::function<cv::Mat(int flags)>& decode) {
  const int flags = as == DecodedImage::kBgr8    ? cv::IMREAD_COLOR
                    : as == DecodedImage::kGray8 ? cv::IMREAD_GRAYSCALE
                                                 : cv::IMREAD_UNCHANGED;
  cv::Mat img;
  try {
    img = decode(flags);
  } catch (const cv::Exception& e) {
    throw InputError(path, "cannot decode image: " + std::string(e.err));
  }
  if (img.empty()) throw InputError(path, "cannot decode image (not a readable PNG/JPEG)");
  if (as == DecodedImage::kDepth16 && img.type() != CV_16UC1)
    throw InputError(path,
                     "depth image must be 16-bit single-channel, found " + describeImageType(img));
  return img;
}

/// PNG and JPEG by their first bytes to libpng and libjpeg, anything else
/// to `other`.
cv::Mat decodeBytes(const std::string& where, const std::string& bytes, DecodedImage as,
                    const std::function<cv::Mat(int flags)>& other) {
  static const unsigned char kPng[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  if (bytes.size() >= 8 && std::memcmp(bytes.data(), kPng, 8) == 0)
    return decodePng(where, bytes, as);
  if (bytes.size() >= 3 && bytes.compare(0, 3, "\xFF\xD8\xFF") == 0)
    return decodeJpeg(where, bytes, as);
  return decodeOther(where, as, other);
}

}  // namespace

cv::Mat decodeImageFile(const std::string& path, DecodedImage as, const std::string& what) {
  const std::string bytes = readRegularFile(path, what, kMaxImageFileBytes);
  return decodeBytes(path, bytes, as, [&](int flags) { return cv::imread(path, flags); });
}

cv::Mat decodeImageBytes(const std::string& bytes, DecodedImage as, const std::string& where) {
  if (bytes.empty()) throw InputError(where, "empty image data");
  if (bytes.size() > kMaxImageFileBytes)
    throw InputError(where,
                     "image data of " + std::to_string(bytes.size()) + " bytes is too large");
  return decodeBytes(where, bytes, as, [&](int flags) {
    return cv::imdecode(
        cv::Mat(1, static_cast<int>(bytes.size()), CV_8UC1, const_cast<char*>(bytes.data())),
        flags);
  });
}

}  // namespace dynslam
