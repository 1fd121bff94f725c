#pragma once
// Ray-casting renderer of the box world.
//
// Per frame and view, a screen-space acceleration structure is built: every box is transformed
// into the camera, clipped against the near plane, and its projected bounding rectangle is
// binned into 16x16-pixel tiles; boxes are inserted in order of their distance to the camera
// centre, so each tile's list is sorted front to back. Rays then go in packets of four
// neighbouring pixels (4-wide vector slab tests) through their tile's boxes only, and stop as
// soon as the next box's distance exceeds the nearest hit of every ray of the packet. The hit
// face is shaded with mip-mapped (brilinear, see Texture::sample) texture sampling through the
// box's per-frame face shaders; when all four rays of a packet hit the same face (the common
// case) they are shaded together in vector form, bit for bit as one at a time. Rays that leave
// the world see the sky. Tile rows of all views are rendered in parallel.
#include <Eigen/Geometry>
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "workloads/datasets/synthetic/world.hpp"

namespace edx::synthetic {

/// Pinhole camera without distortion.
struct PinholeCamera {
  int width = 0, height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  bool operator==(const PinholeCamera&) const = default;
};

struct RenderView {
  PinholeCamera camera;
  Eigen::Isometry3d T_world_camera = Eigen::Isometry3d::Identity();
};

/// Counters of the last render (for benchmarks and tests of the acceleration structure).
struct RenderStats {
  std::int64_t rays = 0;
  std::int64_t box_tests = 0;     ///< slab tests performed
  std::int64_t tile_entries = 0;  ///< box references over all tiles
};

class Renderer {
 public:
  explicit Renderer(const World& world, int threads = 2);

  /// Renders the radiance (CV_32FC1, roughly 0..255) of each view into `out` (resized to the
  /// number of views). Pixel (u, v) is the ray through the pixel centre (u, v) in the
  /// convention x = (u - cx) / fx, u = 0 the centre of the first column.
  /// When `depth` is given, it receives per view the distance along each pixel's unit ray to
  /// the surface hit (CV_32FC1, +inf where the ray sees the sky).
  void render(const std::vector<RenderView>& views, std::vector<cv::Mat>& out,
              std::vector<cv::Mat>* depth = nullptr);

  const RenderStats& last_stats() const { return stats_; }
  int threads() const { return threads_; }

 private:
  static constexpr int kTile = 16;

  struct TileEntry {
    float lo[3];   ///< box.min - camera centre
    float hi[3];   ///< box.max - camera centre
    float d_near;  ///< distance from the camera centre to the box (lower bound of any hit)
    int box;
    int shaders;  ///< index of the box's six face shaders in ViewState::shaders
  };

  /// Per view: unit ray directions in the camera frame and the tile bins (CSR layout).
  struct ViewState {
    PinholeCamera camera;
    std::vector<float> dirs;  ///< 4 floats per pixel: unit direction x, y, z, and z / f
    int tiles_x = 0, tiles_y = 0;
    std::vector<int> tile_begin;  ///< tiles_x * tiles_y + 1 offsets into entries
    std::vector<TileEntry> entries;
    std::vector<FaceShader> shaders;  ///< 6 per visible box, relative to the camera centre
    Eigen::Matrix3f R_world_camera;
    Eigen::Vector3f origin;
  };

  void prepare_directions(ViewState& view, const PinholeCamera& camera) const;
  void bin_boxes(ViewState& view, const RenderView& rv) const;
  /// Renders one row of tiles; returns the number of slab tests.
  std::int64_t render_tile_row(const ViewState& view, int tile_row, cv::Mat& out,
                               cv::Mat* depth) const;

  const World& world_;
  int threads_;
  std::vector<ViewState> views_;
  RenderStats stats_;
};

}  // namespace edx::synthetic
