#include "workloads/frontend/frontend_options.hpp"

#include <string>

namespace edx::frontend {

const FieldList<FrontendOptions>& FrontendOptions::fields() {
  using C = FrontendOptions;
  static const FieldList<C> list = {
      field("features_per_image", &C::features_per_image, "",
            "left image budget: tracked and new features", Bounds::at_least(1)),
      field("right_features_per_image", &C::right_features_per_image, "",
            "right image budget: the candidates left features are matched against",
            Bounds::at_least(1)),
      field("pyramid_levels", &C::pyramid_levels, "", "ORB scale pyramid levels",
            Bounds::at_least(1).at_most(16)),
      field("scale_factor", &C::scale_factor, "", "size ratio of consecutive pyramid levels",
            Bounds::above(1).at_most(2)),
      field("fast_threshold", &C::fast_threshold, "", "FAST intensity threshold",
            Bounds::at_least(1).at_most(254)),
      field("fast_min_threshold", &C::fast_min_threshold, "",
            "retried in grid cells where fast_threshold found nothing (<= fast_threshold)",
            Bounds::at_least(1)),
      field("grid_cell_px", &C::grid_cell_px, "px", "grid cell keypoints are spread over",
            Bounds::at_least(8)),
      field("min_feature_distance_px", &C::min_feature_distance_px, "px",
            "no two left features closer", Bounds::at_least(0)),
      field("right_min_feature_distance_px", &C::right_min_feature_distance_px, "px",
            "no two right keypoints closer", Bounds::at_least(0)),
      field("edge_margin_px", &C::edge_margin_px, "px",
            "no keypoint this close to a level's border (31x31 ORB patch, rotated: >= 19)",
            Bounds::at_least(19)),
      field("gaussian_kernel_px", &C::gaussian_kernel_px, "px", "IF kernel side",
            Bounds::at_least(1).odd_only()),
      field("gaussian_sigma", &C::gaussian_sigma, "px", "IF kernel sigma", Bounds::above(0)),
      field("max_disparity_px", &C::max_disparity_px, "px", "stereo search range along the row",
            Bounds::at_least(1)),
      field("row_band_px", &C::row_band_px, "px", "rows searched either side", Bounds::at_least(0)),
      field("hamming_threshold", &C::hamming_threshold, "bits",
            "the best descriptor distance must not exceed this", Bounds::at_least(0).at_most(256)),
      field("ratio", &C::ratio, "", "best < ratio * second best", Bounds::above(0).at_most(1)),
      field("dr_window_px", &C::dr_window_px, "px", "SAD window side",
            Bounds::at_least(3).odd_only()),
      field("dr_radius_px", &C::dr_radius_px, "px", "SAD search radius around the ORB match",
            Bounds::at_least(1)),
      field("dr_outlier_factor", &C::dr_outlier_factor, "",
            "drop refined matches above this times the frame's median SAD (0: keep all)",
            Bounds::at_least(0)),
      field("lk_window_px", &C::lk_window_px, "px", "LK window side",
            Bounds::at_least(5).at_most(64)),
      field("lk_max_level", &C::lk_max_level, "", "LK pyramid levels above level 0",
            Bounds::at_least(0).at_most(8)),
      field("lk_check_max_level", &C::lk_check_max_level, "",
            "LK pyramid levels of the backward check (<= lk_max_level)", Bounds::at_least(0)),
      field("lk_max_iterations", &C::lk_max_iterations, "",
            "LK iterations per level (OpenCV's limit: 100)", Bounds::at_least(1).at_most(100)),
      field("lk_epsilon_px", &C::lk_epsilon_px, "px",
            "LK termination: update length (OpenCV's limit: 10)", Bounds::above(0).at_most(10)),
      field("lk_min_eigen", &C::lk_min_eigen, "",
            "windows with a smaller normalised minimum eigenvalue are not tracked",
            Bounds::at_least(0)),
      field("fb_threshold_px", &C::fb_threshold_px, "px",
            "forward-backward round trip error allowed", Bounds::above(0)),
      field("count_lk_iterations", &C::count_lk_iterations, "",
            "count the LK iterations of each point (LSS iterations)"),
      field("parallel_images", &C::parallel_images, "",
            "run the frontend's independent chains concurrently"),
  };
  return list;
}

void FrontendOptions::validate() const {
  check_fields(*this, "frontend", fields());
  require_field(fast_min_threshold <= fast_threshold, "frontend", "fast_min_threshold",
                "an integer in [1, fast_threshold]", std::to_string(fast_min_threshold));
  require_field(lk_check_max_level <= lk_max_level, "frontend", "lk_check_max_level",
                "an integer in [0, lk_max_level]", std::to_string(lk_check_max_level));
}

nlohmann::json to_json(const FrontendOptions& options) {
  return fields_to_json(options, FrontendOptions::fields());
}

}  // namespace edx::frontend
