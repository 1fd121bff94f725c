#include "workloads/datasets/image_io.hpp"

#include <fmt/core.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace edx::datasets {

cv::Mat read_gray_image(const std::filesystem::path& file) {
  cv::Mat image;
  try {
    image = cv::imread(file.string(), cv::IMREAD_GRAYSCALE);
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
