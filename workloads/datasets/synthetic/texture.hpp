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

/// Four floats / ints in one SSE register (GCC/Clang vector extensions); comparisons give
/// Int4 masks with true lanes -1.
using Float4 = float __attribute__((vector_size(16)));
using Int4 = std::int32_t __attribute__((vector_size(16)));

inline bool all_lanes(Int4 mask) { return (mask[0] & mask[1] & mask[2] & mask[3]) != 0; }

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

  /// Width of the band of level-of-detail fractions around each integer level that samples
  /// one level only (see sample()).
  static constexpr float kSingleLevelBand = 0.15f;

  /// Trilinear sample with "brilinear" blending: level of detail `lod` = log2(footprint in
  /// level-0 texels), clamped to [0, levels - 1]; with level l = floor(lod) and f = lod - l, the
  /// blend weight of level l + 1 is a = clamp((f - b) / (1 - 2 b), 0, 1), b = kSingleLevelBand,
  /// which is continuous in lod (no seams) but exactly 0 or 1 for half of all fractions, where a
  /// single bilinear sample suffices. Clamped lods sample one level as well.
  float sample(float u, float v, float lod) const {
    const float max_lod = static_cast<float>(level_count_ - 1);
    const float clamped = lod < 0.0f ? 0.0f : (lod > max_lod ? max_lod : lod);
    const int level = static_cast<int>(clamped);
    const float fraction = clamped - static_cast<float>(level);
    constexpr float kScale = 1.0f / (1.0f - 2.0f * kSingleLevelBand);
    const float a = (fraction - kSingleLevelBand) * kScale;
    if (a <= 0.0f) return sample_bilinear(level, u, v);
    if (a >= 1.0f) return sample_bilinear(level + 1, u, v);
    return sample_two_levels(level, u, v, a);
  }

  /// sample() of four points at once, bit for bit equal to four calls: vectorized when all four
  /// lie between the same two levels (the common case of neighbouring pixels on one face), one
  /// lane at a time otherwise.
  Float4 sample4(Float4 u, Float4 v, Float4 lod) const {
    const Float4 max_lod = Float4{} + static_cast<float>(level_count_ - 1);
    const Float4 clamped = lod < 0.0f ? Float4{} : (lod > max_lod ? max_lod : lod);
    const Int4 level = __builtin_convertvector(clamped, Int4);
    const Float4 fraction = clamped - __builtin_convertvector(level, Float4);
    constexpr float kScale = 1.0f / (1.0f - 2.0f * kSingleLevelBand);
    const Float4 a = (fraction - kSingleLevelBand) * kScale;
    if (!all_lanes(level == level[0])) {
      return Float4{sample(u[0], v[0], lod[0]), sample(u[1], v[1], lod[1]),
                    sample(u[2], v[2], lod[2]), sample(u[3], v[3], lod[3])};
    }
    const Int4 fine = a <= 0.0f, coarse = a >= 1.0f;
    if (all_lanes(fine)) return sample_bilinear4(level[0], u, v);
    if (all_lanes(coarse)) return sample_bilinear4(level[0] + 1, u, v);
    // Some lanes blend (so level[0] + 1 exists): both levels, each lane as sample() picks.
    const Float4 fine_value = sample_bilinear4(level[0], u, v);
    const Float4 coarse_value = sample_bilinear4(level[0] + 1, u, v);
    const Float4 blend = fine_value + a * (coarse_value - fine_value);
    return fine ? fine_value : (coarse ? coarse_value : blend);
  }

  /// sample_bilinear() of four points of one level, bit for bit equal to four calls.
  Float4 sample_bilinear4(int level, Float4 u, Float4 v) const {
    const Level& l = levels_[static_cast<std::size_t>(level)];
    const Float4 x = u * l.fsize - 0.5f;
    const Float4 y = v * l.fsize - 0.5f;
    Int4 xi = __builtin_convertvector(x, Int4);  // truncation, then floor: true lanes are -1
    xi += x < __builtin_convertvector(xi, Float4);
    Int4 yi = __builtin_convertvector(y, Int4);
    yi += y < __builtin_convertvector(yi, Float4);
    const Float4 ax = x - __builtin_convertvector(xi, Float4);
    const Float4 ay = y - __builtin_convertvector(yi, Float4);
    const Int4 x0 = xi & l.mask, y0 = yi & l.mask;
    const Int4 x1 = (x0 + 1) & l.mask, y1 = (y0 + 1) & l.mask;
    const Int4 row0 = y0 * l.size, row1 = y1 * l.size;  // < 2^30 texels per level
    const std::uint8_t* texels = texels_.data() + l.offset;
    Int4 t00, t01, t10, t11;
    for (int k = 0; k < 4; ++k) {
      t00[k] = texels[row0[k] + x0[k]];
      t01[k] = texels[row0[k] + x1[k]];
      t10[k] = texels[row1[k] + x0[k]];
      t11[k] = texels[row1[k] + x1[k]];
    }
    const Float4 f00 = __builtin_convertvector(t00, Float4);
    const Float4 f01 = __builtin_convertvector(t01, Float4);
    const Float4 f10 = __builtin_convertvector(t10, Float4);
    const Float4 f11 = __builtin_convertvector(t11, Float4);
    const Float4 top = f00 + ax * (f01 - f00);
    const Float4 bottom = f10 + ax * (f11 - f10);
    return top + ay * (bottom - top);
  }

 private:
  /// Bilinear samples of `level` and `level` + 1 blended with weight `a` of the coarser one.
  /// Branch-free: the coordinates of both levels are computed as one 4-vector (x0, y0, x1, y1).
  float sample_two_levels(int level, float u, float v, float a) const {
    const Level& fine = levels_[static_cast<std::size_t>(level)];
    const Level& coarse = levels_[static_cast<std::size_t>(level + 1)];
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
