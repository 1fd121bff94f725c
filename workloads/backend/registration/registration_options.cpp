#include "workloads/backend/registration/registration_options.hpp"

#include <fmt/format.h>

#include <stdexcept>
#include <string>

namespace edx::backend::registration {
namespace {

template <class T>
void require(bool ok, const char* field, const char* expected, T value) {
  if (!ok) {
    throw std::runtime_error(
        fmt::format("registration option {}: expected {}, got {}", field, expected, value));
  }
}

}  // namespace

void RegistrationOptions::validate() const {
  require(direct_index_level >= 1 && direct_index_level <= 16, "direct_index_level", "1..16",
          direct_index_level);
  require(bow_candidates >= 1, "bow_candidates", ">= 1", bow_candidates);
  require(bow_max_hamming >= 0 && bow_max_hamming <= 256, "bow_max_hamming", "0..256",
          bow_max_hamming);
  require(bow_ratio > 0 && bow_ratio <= 1, "bow_ratio", "(0, 1]", bow_ratio);
  require(pnp_min_matches >= 4, "pnp_min_matches", ">= 4", pnp_min_matches);
  require(pnp_iterations >= 1, "pnp_iterations", ">= 1", pnp_iterations);
  require(pnp_reprojection_px > 0, "pnp_reprojection_px", "> 0", pnp_reprojection_px);
  require(pnp_confidence > 0 && pnp_confidence < 1, "pnp_confidence", "(0, 1)", pnp_confidence);
  require(pnp_min_inliers >= 4, "pnp_min_inliers", ">= 4", pnp_min_inliers);
  require(refinement_rounds >= 1, "refinement_rounds", ">= 1", refinement_rounds);
  require(refinement_iterations >= 1, "refinement_iterations", ">= 1", refinement_iterations);
  require(chi2_threshold > 0, "chi2_threshold", "> 0", chi2_threshold);
  require(octave_scale >= 1, "octave_scale", ">= 1", octave_scale);
  require(tracking_radius_px > 0, "tracking_radius_px", "> 0", tracking_radius_px);
  require(relocalization_radius_px > 0, "relocalization_radius_px", "> 0",
          relocalization_radius_px);
  require(projection_max_hamming >= 0 && projection_max_hamming <= 256, "projection_max_hamming",
          "0..256", projection_max_hamming);
  require(projection_ratio > 0 && projection_ratio <= 1, "projection_ratio", "(0, 1]",
          projection_ratio);
  require(min_depth_m > 0, "min_depth_m", "> 0", min_depth_m);
  require(max_depth_m > min_depth_m, "max_depth_m", "> min_depth_m", max_depth_m);
  require(grid_cell_px >= 1, "grid_cell_px", ">= 1", grid_cell_px);
  require(min_inliers >= 4, "min_inliers", ">= 4", min_inliers);
  require(covisibility_min_shared >= 1, "covisibility_min_shared", ">= 1", covisibility_min_shared);
  require(local_map_neighbours >= 1, "local_map_neighbours", ">= 1", local_map_neighbours);
  require(local_map_max_keyframes >= 1, "local_map_max_keyframes", ">= 1", local_map_max_keyframes);
}

nlohmann::json RegistrationOptions::to_json() const {
  return {{"direct_index_level", direct_index_level},
          {"bow_candidates", bow_candidates},
          {"bow_max_hamming", bow_max_hamming},
          {"bow_ratio", bow_ratio},
          {"pnp_min_matches", pnp_min_matches},
          {"pnp_iterations", pnp_iterations},
          {"pnp_reprojection_px", pnp_reprojection_px},
          {"pnp_confidence", pnp_confidence},
          {"pnp_min_inliers", pnp_min_inliers},
          {"refinement_rounds", refinement_rounds},
          {"refinement_iterations", refinement_iterations},
          {"chi2_threshold", chi2_threshold},
          {"octave_scale", octave_scale},
          {"tracking_radius_px", tracking_radius_px},
          {"relocalization_radius_px", relocalization_radius_px},
          {"projection_max_hamming", projection_max_hamming},
          {"projection_ratio", projection_ratio},
          {"min_depth_m", min_depth_m},
          {"max_depth_m", max_depth_m},
          {"grid_cell_px", grid_cell_px},
          {"min_inliers", min_inliers},
          {"local_map", local_map},
          {"covisibility_min_shared", covisibility_min_shared},
          {"local_map_neighbours", local_map_neighbours},
          {"local_map_max_keyframes", local_map_max_keyframes},
          {"constant_velocity", constant_velocity}};
}

}  // namespace edx::backend::registration
