#include "workloads/datasets/image_io.hpp"

#include <fmt/core.h>
#include <zlib.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <vector>

namespace edx::datasets {
namespace {

constexpr std::array<unsigned char, 8> kPngSignature = {0x89, 'P',  'N',  'G',
                                                        '\r', '\n', 0x1a, '\n'};

std::uint32_t big_endian_u32(const unsigned char* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) |
         std::uint32_t{p[3]};
}

/// Walks a PNG's chunks (PNG spec, sec. 5.3: length, type, data, CRC-32 of type and data) up to
/// IEND, so that a truncated or damaged file is one error of ours rather than a line libpng
/// prints on its own before OpenCV returns an empty image. Not covered: a deflate stream damaged
/// under valid CRCs (only a deliberately crafted file), which libpng still reports itself.
void check_png_chunks(const std::vector<unsigned char>& bytes, const std::filesystem::path& file) {
  std::size_t at = kPngSignature.size();
  while (true) {
    if (bytes.size() - at < 12) {
      throw std::runtime_error(fmt::format(
          "{}: truncated PNG ({} bytes, ends before its IEND chunk)", file.string(), bytes.size()));
    }
    const std::uint64_t length = big_endian_u32(&bytes[at]);
    if (length > bytes.size() - at - 12) {
      throw std::runtime_error(fmt::format(
          "{}: truncated PNG ({} bytes; the chunk at byte {} declares {} bytes of data)",
          file.string(), bytes.size(), at, length));
    }
    const unsigned char* type = &bytes[at + 4];
    const uLong crc = ::crc32(::crc32(0L, Z_NULL, 0), type, static_cast<uInt>(length + 4));
    if (crc != big_endian_u32(type + 4 + length)) {
      throw std::runtime_error(
          fmt::format("{}: damaged PNG (the {} chunk at byte {} fails its CRC)", file.string(),
                      std::string(reinterpret_cast<const char*>(type), 4), at));
    }
    if (std::memcmp(type, "IEND", 4) == 0) return;
    at += 12 + length;
  }
}

}  // namespace

cv::Mat read_gray_image(const std::filesystem::path& file) {
  std::vector<unsigned char> bytes;
  {
    // One read of the whole file (an istreambuf_iterator copy goes byte by byte: ~2 % of a
    // trace's CPU time at 1280x720).
    std::error_code ec;
    const std::uintmax_t size =
        std::filesystem::is_regular_file(file, ec) ? std::filesystem::file_size(file, ec) : 0;
    std::ifstream in(file, std::ios::binary);
    if (in && !ec && size > 0) {
      bytes.resize(static_cast<std::size_t>(size));
      if (!in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(size))) {
        bytes.clear();  // shorter than its size said (changed meanwhile): reported as unreadable
      }
    }
  }
  const bool png = bytes.size() >= kPngSignature.size() &&
                   std::equal(kPngSignature.begin(), kPngSignature.end(), bytes.begin());
  if (png) check_png_chunks(bytes, file);
  cv::Mat image;
  try {
    if (!bytes.empty()) image = cv::imdecode(bytes, cv::IMREAD_GRAYSCALE);
  } catch (const cv::Exception& e) {
    throw std::runtime_error(fmt::format("{}: cannot read image: {}", file.string(), e.what()));
  }
  if (image.empty()) {
    throw std::runtime_error(
        fmt::format("{}: cannot read image (missing, unreadable or not an image)", file.string()));
  }
  return image;
}

cv::Mat read_gray_image(const std::filesystem::path& file, cv::Size expected_size,
                        std::string_view size_source) {
  cv::Mat image = read_gray_image(file);
  if (image.size() != expected_size) {
    throw std::runtime_error(fmt::format("{}: image is {}x{}, expected {}x{} ({})", file.string(),
                                         image.cols, image.rows, expected_size.width,
                                         expected_size.height, size_source));
  }
  return image;
}

CameraIntrinsics scale_intrinsics(const CameraIntrinsics& intrinsics, cv::Size target) {
  if (!intrinsics.distortion.empty()) {
    throw std::logic_error("scale_intrinsics: only undistorted (rectified) intrinsics scale");
  }
  if (target.width <= 0 || target.height <= 0) {
    throw std::runtime_error(fmt::format("resize target {}x{}: width and height must be positive",
                                         target.width, target.height));
  }
  if (intrinsics.width <= 0 || intrinsics.height <= 0) {
    throw std::logic_error("scale_intrinsics: the source image size must be positive");
  }
  const double sx = static_cast<double>(target.width) / intrinsics.width;
  const double sy = static_cast<double>(target.height) / intrinsics.height;
  CameraIntrinsics scaled;
  scaled.width = target.width;
  scaled.height = target.height;
  scaled.fx = intrinsics.fx * sx;
  scaled.fy = intrinsics.fy * sy;
  scaled.cx = (intrinsics.cx + 0.5) * sx - 0.5;
  scaled.cy = (intrinsics.cy + 0.5) * sy - 0.5;
  return scaled;
}

cv::Mat resize_image(const cv::Mat& image, cv::Size target) {
  if (image.size() == target) return image;
  const bool shrinking = target.width <= image.cols && target.height <= image.rows;
  cv::Mat resized;
  cv::resize(image, resized, target, 0, 0, shrinking ? cv::INTER_AREA : cv::INTER_LINEAR);
  return resized;
}

}  // namespace edx::datasets
