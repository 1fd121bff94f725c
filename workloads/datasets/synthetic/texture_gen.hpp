#pragma once
// Procedural texture images for the synthetic world, all generated from a seed: multi-octave
// value noise (fractional Brownian motion), bricks, panels, posters with text, barcodes,
// clutter, windows, foliage. Every image is square, 8-bit, power-of-two sized and tiles
// seamlessly (shapes are drawn at all nine periodic offsets), so that it can be repeated over
// large faces. The mix of sharp-edged shapes at several sizes and noise at several octaves gives
// corners at several scales, as real scenes do.
#include <cstdint>
#include <opencv2/core.hpp>
#include <string_view>

#include "workloads/datasets/synthetic/random.hpp"

namespace edx::synthetic {

enum class TextureKind {
  kConcrete,      ///< floor slab: noise, stains, speckles, cracks, joints
  kBricks,        ///< brick wall with mortar
  kMetalPanels,   ///< corrugated wall cladding with seams, rivets and stickers
  kCeiling,       ///< ceiling panels with light fixtures and vents
  kCardboard,     ///< carton: tape, labels with text, barcodes
  kPoster,        ///< shapes, large and small text
  kShelfUpright,  ///< painted steel with punched holes
  kShelfBeam,     ///< painted steel beam with location labels
  kWood,          ///< pallet planks with grain and knots
  kClutter,       ///< random shapes at several scales on noise
  kAsphalt,       ///< road surface: grain, patches, cracks
  kPaint,         ///< worn white paint (road markings, floor tape)
  kPavers,        ///< sidewalk slabs
  kFacade,        ///< building facade module: 2 floors x 3 windows
  kShopFront,     ///< shop window with sign text
  kCarSide,       ///< car body side: paint, doors, wheels
  kCarEnd,        ///< car front/back: lights, grille, plate
  kCarGlass,      ///< car cabin: windows and pillars
  kFoliage,       ///< tree crown: leaf clumps
  kBark,          ///< tree trunk / pole
  kClouds,        ///< sky: large soft clouds
};

std::string_view to_string(TextureKind kind);

/// Fractional Brownian motion of tileable value noise, CV_32FC1 in [0, 1] (min-max normalized).
/// `base_cells` random values per side at the coarsest octave (a power of two dividing
/// `size`), doubling each octave; amplitude multiplied by `persistence` per octave.
cv::Mat fbm_noise(Rng& rng, int size, int base_cells, int octaves, double persistence);

/// Generates a texture of `kind`, side `size` (power of two >= 64), from `seed`.
cv::Mat make_texture_image(TextureKind kind, std::uint64_t seed, int size = 512);

}  // namespace edx::synthetic
