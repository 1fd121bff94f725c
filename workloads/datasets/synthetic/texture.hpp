#pragma once
// A tileable, mip-mapped 8-bit grayscale texture with bilinear and trilinear sampling.
//
// Texture coordinates (u, v) are measured in tiles: the texture repeats with period 1 in both.
// Level 0 is the full-resolution image (square, power-of-two side); level l+1 is the 2x2 box
// average of level l, so every level tiles as the base does.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

namespace edx::synthetic {

/// floor(x) as int for |x| < 2^31, without a library call (baseline x86-64 has no roundss).
inline int floor_to_int(float x) {
  const int truncated = static_cast<int>(x);
  return truncated - (x < static_cast<float>(truncated) ? 1 : 0);
}

class Texture {
 public:
  /// `image` must be CV_8UC1, square, with a power-of-two side of at least 4 texels.
  explicit Texture(const cv::Mat& image);

  int size() const { return levels_[0].size; }
  int level_count() const { return level_count_; }
  /// The level-0 image (a copy is not made; do not modify).
  const cv::Mat& image() const { return image_; }

  /// Bilinear sample of `level` at (u, v) tiles; texel centres sit at (i + 0.5) / size.
  /// Returns the interpolated value in [0, 255].
  float sample_bilinear(int level, float u, float v) const {
    const Level& l = levels_[static_cast<std::size_t>(level)];
    const float x = u * l.fsize - 0.5f;
    const float y = v * l.fsize - 0.5f;
    const int xi = floor_to_int(x);
    const int yi = floor_to_int(y);
    const float ax = x - static_cast<float>(xi);
    const float ay = y - static_cast<float>(yi);
    const int x0 = xi & l.mask;
    const int y0 = yi & l.mask;
    const int x1 = (x0 + 1) & l.mask;
    const int y1 = (y0 + 1) & l.mask;
    const std::uint8_t* texels = texels_.data() + l.offset;
    const std::uint8_t* row0 = texels + static_cast<std::size_t>(y0) * l.size;
    const std::uint8_t* row1 = texels + static_cast<std::size_t>(y1) * l.size;
    const float top = row0[x0] + ax * (static_cast<float>(row0[x1]) - row0[x0]);
    const float bottom = row1[x0] + ax * (static_cast<float>(row1[x1]) - row1[x0]);
    return top + ay * (bottom - top);
  }

  /// Trilinear sample: level of detail `lod` = log2(footprint in level-0 texels), clamped to
  /// [0, levels - 1]; bilinear samples of the two nearest levels blended linearly. Branch-free:
  /// the coordinates of both levels are computed as one 4-vector (x0, y0, x1, y1).
  float sample(float u, float v, float lod) const {
    using Float4 = float __attribute__((vector_size(16)));
    using Int4 = std::int32_t __attribute__((vector_size(16)));
    const float max_lod = static_cast<float>(level_count_ - 1);
    const float clamped = lod < 0.0f ? 0.0f : (lod > max_lod ? max_lod : lod);
    const int level = static_cast<int>(clamped);
    const float a = clamped - static_cast<float>(level);
    const Level& fine = levels_[static_cast<std::size_t>(level)];
    const Level& coarse = levels_[static_cast<std::size_t>(std::min(level + 1, level_count_ - 1))];
    const Float4 xy =
        Float4{u * fine.fsize, v * fine.fsize, u * coarse.fsize, v * coarse.fsize} - 0.5f;
    Int4 cell = __builtin_convertvector(xy, Int4);       // truncation, then floor:
    cell += xy < __builtin_convertvector(cell, Float4);  // true lanes are -1
    const Float4 frac = xy - __builtin_convertvector(cell, Float4);
    const Int4 mask = {fine.mask, fine.mask, coarse.mask, coarse.mask};
    const Int4 c0 = cell & mask, c1 = (cell + 1) & mask;
    const std::uint8_t* tf = texels_.data() + fine.offset;
    const std::uint8_t* tc = texels_.data() + coarse.offset;
    const std::uint8_t* f0 = tf + static_cast<std::size_t>(c0[1]) * fine.size;
    const std::uint8_t* f1 = tf + static_cast<std::size_t>(c1[1]) * fine.size;
    const std::uint8_t* g0 = tc + static_cast<std::size_t>(c0[3]) * coarse.size;
    const std::uint8_t* g1 = tc + static_cast<std::size_t>(c1[3]) * coarse.size;
    // Rows (top, bottom) of both levels, interpolated along x, then along y, then across levels.
    const Float4 left = {static_cast<float>(f0[c0[0]]), static_cast<float>(f1[c0[0]]),
                         static_cast<float>(g0[c0[2]]), static_cast<float>(g1[c0[2]])};
    const Float4 right = {static_cast<float>(f0[c1[0]]), static_cast<float>(f1[c1[0]]),
                          static_cast<float>(g0[c1[2]]), static_cast<float>(g1[c1[2]])};
    const Float4 ax = {frac[0], frac[0], frac[2], frac[2]};
    const Float4 rows = left + ax * (right - left);
    const float fine_value = rows[0] + frac[1] * (rows[1] - rows[0]);
    const float coarse_value = rows[2] + frac[3] * (rows[3] - rows[2]);
    return fine_value + a * (coarse_value - fine_value);
  }

 private:
  static constexpr int kMaxLevels = 16;  // sides up to 2^15
  struct Level {
    std::size_t offset = 0;  ///< first texel in texels_
    int size = 0;
    int mask = 0;
    float fsize = 0;
  };
  cv::Mat image_;
  std::vector<std::uint8_t> texels_;  ///< all levels, level 0 first
  std::array<Level, kMaxLevels> levels_{};
  int level_count_ = 0;
};

}  // namespace edx::synthetic
