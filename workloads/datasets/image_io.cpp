#include "workloads/datasets/image_io.hpp"

#include <fmt/core.h>

#include <cstdint>
#include <fstream>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <vector>

#include "workloads/datasets/png_io.hpp"

namespace edx::datasets {

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
  if (bytes.empty()) {
    throw std::runtime_error(
        fmt::format("{}: cannot read image (missing, unreadable or empty)", file.string()));
  }
  return decode_png_gray(bytes, file);
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
