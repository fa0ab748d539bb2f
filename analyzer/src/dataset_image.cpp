#include "aar/analyzer/dataset_image.h"

#include <png.h>

#include <algorithm>
#include <csetjmp>
#include <cstring>
#include <initializer_list>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "aar/error.h"
#include "aar/png_check.h"

namespace aar {
namespace {

// libpng's read callback over the file's bytes.
struct MemoryReader {
  std::string_view bytes;
  size_t at = 0;
};

void ReadFromMemory(png_structp png, png_bytep out, png_size_t length) {
  auto* reader = static_cast<MemoryReader*>(png_get_io_ptr(png));
  if (length > reader->bytes.size() - reader->at) png_error(png, "read past the end");
  std::memcpy(out, reader->bytes.data() + reader->at, length);
  reader->at += length;
}

// libpng reports errors by longjmp; its messages are replaced by ours.
void ErrorToJump(png_structp png, png_const_charp) { png_longjmp(png, 1); }
void IgnoreWarning(png_structp, png_const_charp) {}

// Reads an 8-bit, non-interlaced grey or RGB PNG with libpng into `image`
// (allocated here) as cv::imdecode would with `flags`, without the
// checksums (DecodeVerifiedPng); false for other files, or when libpng fails. The
// caller owns everything with a destructor, so libpng's longjmp skips none.
bool ReadPng(png_structp png, png_infop info, int flags, cv::Mat* image, std::vector<png_bytep>* rows) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_set_crc_action(png, PNG_CRC_QUIET_USE, PNG_CRC_QUIET_USE);
  png_set_option(png, PNG_IGNORE_ADLER32, PNG_OPTION_ON);
  png_read_info(png, info);
  const png_uint_32 width = png_get_image_width(png, info), height = png_get_image_height(png, info);
  const int colour = png_get_color_type(png, info);
  const bool grey = colour == PNG_COLOR_TYPE_GRAY;
  if (png_get_bit_depth(png, info) != 8 || png_get_interlace_type(png, info) != PNG_INTERLACE_NONE ||
      (colour != PNG_COLOR_TYPE_GRAY && colour != PNG_COLOR_TYPE_RGB) || png_get_valid(png, info, PNG_INFO_tRNS) ||
      (flags == cv::IMREAD_GRAYSCALE && !grey) || width == 0 || height == 0 || width > (1u << 16) ||
      height > (1u << 16)) {
    return false;
  }
  int channels = grey ? 1 : 3;
  if (grey && flags == cv::IMREAD_COLOR) {
    png_set_gray_to_rgb(png);
    channels = 3;
  }
  if (channels == 3) png_set_bgr(png);
  png_read_update_info(png, info);
  image->create(static_cast<int>(height), static_cast<int>(width), CV_8UC(channels));
  rows->resize(height);
  for (png_uint_32 y = 0; y < height; ++y) (*rows)[y] = image->ptr<png_byte>(static_cast<int>(y));
  png_read_image(png, rows->data());
  png_read_end(png, nullptr);
  return true;
}

// ReadPng with libpng's set-up around it; empty for other files and flags.
cv::Mat DecodeLibpng(std::string_view bytes, int flags) {
  if (flags != cv::IMREAD_COLOR && flags != cv::IMREAD_UNCHANGED && flags != cv::IMREAD_GRAYSCALE) return {};
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, nullptr, ErrorToJump, IgnoreWarning);
  if (png == nullptr) return {};
  png_infop info = png_create_info_struct(png);
  MemoryReader reader{bytes, 0};
  cv::Mat image;
  std::vector<png_bytep> rows;
  bool read = false;
  if (info != nullptr) {
    png_set_read_fn(png, &reader, ReadFromMemory);
    read = ReadPng(png, info, flags, &image, &rows);
  }
  png_destroy_read_struct(&png, info != nullptr ? &info : nullptr, nullptr);
  return read ? image : cv::Mat();
}

}  // namespace

cv::Mat DecodeVerifiedPng(std::string_view bytes, int flags) {
  cv::Mat image = DecodeLibpng(bytes, flags);
  if (image.empty()) {
    image = cv::imdecode(cv::Mat(1, static_cast<int>(bytes.size()), CV_8U, const_cast<char*>(bytes.data())), flags);
  }
  return image;
}

namespace {

// The images of one window (the thermal views of a pair, or one alone),
// their joint coldest count to 0 and hottest to 255, as 8-bit BGR.
void WindowThermal(std::initializer_list<cv::Mat*> images, const std::string& where) {
  double lo = 0.0, hi = 0.0;
  bool first = true;
  for (const cv::Mat* image : images) {
    if (image->type() != CV_16UC1) {
      throw Error(where + ": the rig declares an LWIR camera, the image is not one-channel 16-bit (radiometric)");
    }
    double image_lo = 0.0, image_hi = 0.0;
    cv::minMaxLoc(*image, &image_lo, &image_hi);
    lo = first ? image_lo : std::min(lo, image_lo);
    hi = first ? image_hi : std::max(hi, image_hi);
    first = false;
  }
  const double scale = hi > lo ? 255.0 / (hi - lo) : 0.0;
  for (cv::Mat* image : images) {
    cv::Mat grey;
    image->convertTo(grey, CV_8U, scale, -lo * scale);  // saturating, round to nearest
    cv::cvtColor(grey, *image, cv::COLOR_GRAY2BGR);
  }
}

}  // namespace

void WindowThermalPair(cv::Mat& left, cv::Mat& right, const std::string& where) {
  WindowThermal({&left, &right}, where);
}

void WindowThermalImage(cv::Mat& image, const std::string& where) { WindowThermal({&image}, where); }

cv::Mat ReadListedImage(const OpenedDataset& dataset, const FileRef& ref, int flags, const std::string& what) {
  const std::string path = dataset.PathOf(ref.path);
  const std::string bytes = dataset.ReadFile(ref);
  CheckPngStructure(bytes, path);
  const cv::Mat image = DecodeVerifiedPng(bytes, flags);
  if (image.empty()) throw Error(path + ": cannot decode " + what);
  return image;
}

}  // namespace aar
