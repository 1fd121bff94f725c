#include "workloads/backend/registration/registration_options.hpp"

#include "workloads/trace/precision_field.hpp"

namespace edx::backend::registration {

const FieldList<RegistrationOptions>& RegistrationOptions::fields() {
  using C = RegistrationOptions;
  static const FieldList<C> list = {
      trace::precision_field(
          &C::precision,
          "arithmetic of the offloadable kernels (projection): fp64 or fp32 (docs/TRACE.md)"),
      field("direct_index_level", &C::direct_index_level, "",
            "vocabulary level of the direct index, from the root", Bounds::at_least(1).at_most(16)),
      field("bow_candidates", &C::bow_candidates, "", "keyframes matched after a query",
            Bounds::at_least(1)),
      field("bow_max_hamming", &C::bow_max_hamming, "bits",
            "accepted descriptor distance (ORB-SLAM TH_LOW)", Bounds::at_least(0).at_most(256)),
      field("bow_ratio", &C::bow_ratio, "", "best < ratio * second best",
            Bounds::above(0).at_most(1)),
      field("pnp_min_matches", &C::pnp_min_matches, "",
            "a candidate with fewer 2D-3D matches is skipped", Bounds::at_least(4)),
      field("pnp_iterations", &C::pnp_iterations, "", "RANSAC iterations", Bounds::at_least(1)),
      field("pnp_reprojection_px", &C::pnp_reprojection_px, "px", "RANSAC inlier threshold",
            Bounds::above(0)),
      field("pnp_confidence", &C::pnp_confidence, "", "RANSAC confidence",
            Bounds::above(0).below(1)),
      field("pnp_min_inliers", &C::pnp_min_inliers, "",
            "a candidate's PnP below this counts as failed", Bounds::at_least(4)),
      field("refinement_rounds", &C::refinement_rounds, "",
            "pose refinement rounds (outliers set aside after each)", Bounds::at_least(1)),
      field("refinement_iterations", &C::refinement_iterations, "",
            "Gauss-Newton iterations per round", Bounds::at_least(1)),
      field("chi2_threshold", &C::chi2_threshold, "", "outlier gate of a whitened error",
            Bounds::above(0)),
      field("octave_scale", &C::octave_scale, "", "the frontend's pyramid scale factor",
            Bounds::at_least(1)),
      field("tracking_radius_px", &C::tracking_radius_px, "px",
            "search window around the predicted projection", Bounds::above(0)),
      field("relocalization_radius_px", &C::relocalization_radius_px, "px",
            "search window after PnP", Bounds::above(0)),
      field("projection_max_hamming", &C::projection_max_hamming, "bits",
            "accepted descriptor distance in the projection search",
            Bounds::at_least(0).at_most(256)),
      field("projection_ratio", &C::projection_ratio, "",
            "best < ratio * second best in the window", Bounds::above(0).at_most(1)),
      field("min_depth_m", &C::min_depth_m, "m", "nearer map points are not searched",
            Bounds::above(0)),
      field("max_depth_m", &C::max_depth_m, "m", "nor farther ones (> min_depth_m)"),
      field("grid_cell_px", &C::grid_cell_px, "px", "feature grid cell for window searches",
            Bounds::at_least(1)),
      field("min_inliers", &C::min_inliers, "",
            "inliers of the last refinement that register a frame", Bounds::at_least(4)),
      field("local_map", &C::local_map, "",
            "project ORB-SLAM's local map each frame (false: the whole map)"),
      field("covisibility_min_shared", &C::covisibility_min_shared, "",
            "map points two keyframes share to be covisible", Bounds::at_least(1)),
      field("local_map_neighbours", &C::local_map_neighbours, "",
            "best covisible keyframes looked at per keyframe", Bounds::at_least(1)),
      field("local_map_max_keyframes", &C::local_map_max_keyframes, "",
            "most keyframes of the local map", Bounds::at_least(1)),
      field("constant_velocity", &C::constant_velocity, "",
            "predict the pose by constant velocity (false: the previous pose)"),
  };
  return list;
}

void RegistrationOptions::validate() const {
  check_fields(*this, "registration", fields());
  require_field(max_depth_m > min_depth_m, "registration", "max_depth_m", "a number > min_depth_m",
                field_value_text(max_depth_m));
}

nlohmann::json RegistrationOptions::to_json() const { return fields_to_json(*this, fields()); }

}  // namespace edx::backend::registration
