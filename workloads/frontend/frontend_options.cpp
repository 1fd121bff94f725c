#include "workloads/frontend/frontend_options.hpp"

#include <fmt/core.h>

#include <stdexcept>
#include <string_view>

namespace edx::frontend {
namespace {

template <typename T>
void require(bool ok, std::string_view name, T value, std::string_view expected) {
  if (!ok) {
    throw std::runtime_error(
        fmt::format("frontend option {} = {} (expected {})", name, value, expected));
  }
}

}  // namespace

void FrontendOptions::validate() const {
  require(features_per_image >= 1, "features_per_image", features_per_image, ">= 1");
  require(right_features_per_image >= 1, "right_features_per_image", right_features_per_image,
          ">= 1");
  require(pyramid_levels >= 1 && pyramid_levels <= 16, "pyramid_levels", pyramid_levels, "1..16");
  require(scale_factor > 1.0 && scale_factor <= 2.0, "scale_factor", scale_factor, "in (1, 2]");
  require(fast_threshold >= 1 && fast_threshold <= 254, "fast_threshold", fast_threshold, "1..254");
  require(fast_min_threshold >= 1 && fast_min_threshold <= fast_threshold, "fast_min_threshold",
          fast_min_threshold, "1..fast_threshold");
  require(grid_cell_px >= 8, "grid_cell_px", grid_cell_px, ">= 8");
  require(min_feature_distance_px >= 0, "min_feature_distance_px", min_feature_distance_px, ">= 0");
  require(right_min_feature_distance_px >= 0, "right_min_feature_distance_px",
          right_min_feature_distance_px, ">= 0");
  require(edge_margin_px >= 19, "edge_margin_px", edge_margin_px,
          ">= 19 (31x31 ORB patch, rotated)");
  require(gaussian_kernel_px >= 1 && gaussian_kernel_px % 2 == 1, "gaussian_kernel_px",
          gaussian_kernel_px, "an odd number >= 1");
  require(gaussian_sigma > 0, "gaussian_sigma", gaussian_sigma, "> 0");
  require(max_disparity_px >= 1, "max_disparity_px", max_disparity_px, ">= 1");
  require(row_band_px >= 0, "row_band_px", row_band_px, ">= 0");
  require(hamming_threshold >= 0 && hamming_threshold <= 256, "hamming_threshold",
          hamming_threshold, "0..256");
  require(ratio > 0 && ratio <= 1, "ratio", ratio, "in (0, 1]");
  require(dr_window_px >= 3 && dr_window_px % 2 == 1, "dr_window_px", dr_window_px,
          "an odd number >= 3");
  require(dr_radius_px >= 1, "dr_radius_px", dr_radius_px, ">= 1");
  require(dr_outlier_factor >= 0, "dr_outlier_factor", dr_outlier_factor, ">= 0");
  require(lk_window_px >= 5 && lk_window_px <= 64, "lk_window_px", lk_window_px, "5..64");
  require(lk_max_level >= 0 && lk_max_level <= 8, "lk_max_level", lk_max_level, "0..8");
  require(lk_check_max_level >= 0 && lk_check_max_level <= lk_max_level, "lk_check_max_level",
          lk_check_max_level, "0..lk_max_level");
  require(lk_max_iterations >= 1 && lk_max_iterations <= 100, "lk_max_iterations",
          lk_max_iterations, "1..100 (OpenCV's limit)");
  require(lk_epsilon_px > 0 && lk_epsilon_px <= 10, "lk_epsilon_px", lk_epsilon_px,
          "in (0, 10] (OpenCV's limit)");
  require(lk_min_eigen >= 0, "lk_min_eigen", lk_min_eigen, ">= 0");
  require(fb_threshold_px > 0, "fb_threshold_px", fb_threshold_px, "> 0");
}

nlohmann::json to_json(const FrontendOptions& o) {
  return {
      {"features_per_image", o.features_per_image},
      {"right_features_per_image", o.right_features_per_image},
      {"pyramid_levels", o.pyramid_levels},
      {"scale_factor", o.scale_factor},
      {"fast_threshold", o.fast_threshold},
      {"fast_min_threshold", o.fast_min_threshold},
      {"grid_cell_px", o.grid_cell_px},
      {"min_feature_distance_px", o.min_feature_distance_px},
      {"right_min_feature_distance_px", o.right_min_feature_distance_px},
      {"edge_margin_px", o.edge_margin_px},
      {"gaussian_kernel_px", o.gaussian_kernel_px},
      {"gaussian_sigma", o.gaussian_sigma},
      {"max_disparity_px", o.max_disparity_px},
      {"row_band_px", o.row_band_px},
      {"hamming_threshold", o.hamming_threshold},
      {"ratio", o.ratio},
      {"dr_window_px", o.dr_window_px},
      {"dr_radius_px", o.dr_radius_px},
      {"dr_outlier_factor", o.dr_outlier_factor},
      {"lk_window_px", o.lk_window_px},
      {"lk_max_level", o.lk_max_level},
      {"lk_check_max_level", o.lk_check_max_level},
      {"lk_max_iterations", o.lk_max_iterations},
      {"lk_epsilon_px", o.lk_epsilon_px},
      {"lk_min_eigen", o.lk_min_eigen},
      {"fb_threshold_px", o.fb_threshold_px},
      {"count_lk_iterations", o.count_lk_iterations},
      {"parallel_images", o.parallel_images},
  };
}

}  // namespace edx::frontend
