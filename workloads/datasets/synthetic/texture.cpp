#include "workloads/datasets/synthetic/texture.hpp"

#include <stdexcept>
#include <string>

namespace edx::synthetic {

Texture::Texture(const cv::Mat& image) {
  const bool power_of_two = image.cols > 0 && (image.cols & (image.cols - 1)) == 0;
  if (image.type() != CV_8UC1 || image.rows != image.cols || !power_of_two || image.cols < 4) {
    throw std::runtime_error(
        "synthetic texture: expected a square 8-bit image with a power-of-two "
        "side >= 4, got " +
        std::to_string(image.cols) + "x" + std::to_string(image.rows));
  }
  if (image.cols > (1 << (kMaxLevels - 1))) {
    throw std::runtime_error("synthetic texture: side " + std::to_string(image.cols) +
                             " larger than supported");
  }
  image_ = image.clone();
  cv::Mat level = image_;
  while (true) {
    Level& l = levels_[static_cast<std::size_t>(level_count_++)];
    l.offset = texels_.size();
    l.size = level.cols;
    l.mask = l.size - 1;
    l.fsize = static_cast<float>(l.size);
    texels_.insert(texels_.end(), level.datastart, level.datastart + level.total());
    if (level.cols == 1) break;
    // 2x2 box average with rounding: keeps the periodicity of the level above.
    cv::Mat next(level.rows / 2, level.cols / 2, CV_8UC1);
    for (int y = 0; y < next.rows; ++y) {
      const std::uint8_t* r0 = level.ptr<std::uint8_t>(2 * y);
      const std::uint8_t* r1 = level.ptr<std::uint8_t>(2 * y + 1);
      std::uint8_t* out = next.ptr<std::uint8_t>(y);
      for (int x = 0; x < next.cols; ++x) {
        const int sum = r0[2 * x] + r0[2 * x + 1] + r1[2 * x] + r1[2 * x + 1];
        out[x] = static_cast<std::uint8_t>((sum + 2) / 4);
      }
    }
    level = next;
  }
}

}  // namespace edx::synthetic
