#pragma once
// Image loading with size checks, and the output resize shared by every dataset reader.
#include <filesystem>
#include <opencv2/core.hpp>
#include <string_view>

#include "workloads/datasets/dataset.hpp"

namespace edx::datasets {

/// Reads the PNG `file` as 8-bit grayscale (decode_png_gray, png_io.hpp: the pixels of
/// cv::imread(file, cv::IMREAD_GRAYSCALE)); throws std::runtime_error naming the file when it is
/// missing, empty, not a PNG ("expected a PNG image") or cannot be decoded.
cv::Mat read_gray_image(const std::filesystem::path& file);

/// Reads `file` as 8-bit grayscale. Throws std::runtime_error naming the file when it cannot be
/// decoded, or when its size differs from `expected_size` (`size_source` says where that size
/// was declared, e.g. "cam0/sensor.yaml resolution").
cv::Mat read_gray_image(const std::filesystem::path& file, cv::Size expected_size,
                        std::string_view size_source);

/// Intrinsics of an image resized to `target` (pixel-centre convention of cv::resize):
/// with sx = W'/W, sy = H'/H: fx' = fx*sx, fy' = fy*sy, cx' = (cx+0.5)*sx - 0.5,
/// cy' = (cy+0.5)*sy - 0.5. Distortion must be empty (only rectified images are resized).
CameraIntrinsics scale_intrinsics(const CameraIntrinsics& intrinsics, cv::Size target);

/// Resizes `image` to `target`: cv::INTER_AREA when shrinking in both directions (averages the
/// covered source pixels, no aliasing), cv::INTER_LINEAR otherwise. Both keep pixel centres
/// aligned as scale_intrinsics assumes. Returns `image` itself when the size already matches.
cv::Mat resize_image(const cv::Mat& image, cv::Size target);

}  // namespace edx::datasets
