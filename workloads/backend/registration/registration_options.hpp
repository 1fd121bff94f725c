#pragma once
// Options of the registration backend (paper Sec. IV-A, registration mode: localization against a
// prebuilt map). Defaults follow ORB-SLAM's tracking and relocalization where it has a value
// (Mur-Artal et al.: BoW matching at TH_LOW = 50 with ratio 0.75, motion-only BA with chi-square
// 5.991 at 95 % for 2 DoF in four rounds, pyramid scale 1.2 for the pixel sigma).
#include <cstddef>
#include <nlohmann/json.hpp>

#include "common/config_fields.hpp"
#include "workloads/backend/registration/covisibility.hpp"
#include "workloads/trace/records.hpp"

namespace edx::backend::registration {

struct RegistrationOptions {
  /// The arithmetic of the offloadable kernel (projection): the workload's precision.
  trace::Precision precision = trace::Precision::kFp64;
  // Keyframe-database query (bow_query) and BoW descriptor matching (matching).
  int direct_index_level = 2;      ///< vocabulary level of the direct index, from the root
  std::size_t bow_candidates = 5;  ///< keyframes matched after a query (best scores)
  int bow_max_hamming = 50;        ///< accepted descriptor distance (ORB-SLAM TH_LOW)
  double bow_ratio = 0.75;         ///< best < ratio * second best (ORB-SLAM relocalization)

  // RANSAC PnP (pnp), per candidate keyframe.
  int pnp_min_matches = 15;          ///< a candidate with fewer 2D-3D matches is skipped
  int pnp_iterations = 200;          ///< RANSAC iterations (EPnP on minimal sets)
  double pnp_reprojection_px = 4.0;  ///< inlier threshold, px
  double pnp_confidence = 0.99;
  int pnp_min_inliers = 12;  ///< a candidate's PnP below this counts as failed

  // Motion-only refinement (pose_refinement): Gauss-Newton on whitened reprojection errors
  // e = (pi(R X + t) - z) / sigma, sigma = octave_scale^octave px, Huber loss at sqrt(chi2),
  // rounds of iterations after each of which matches with e^2 > chi2 are set aside.
  int refinement_rounds = 4;
  int refinement_iterations = 10;
  double chi2_threshold = 5.991;  ///< chi-square 95 % for 2 DoF
  double octave_scale = 1.2;      ///< the frontend's pyramid scale factor

  // Tracking by projection (projection, projection_matching).
  double tracking_radius_px = 15;       ///< search window around the predicted projection
  double relocalization_radius_px = 8;  ///< after PnP (pose already close)
  int projection_max_hamming = 64;      ///< accepted descriptor distance
  double projection_ratio = 0.9;        ///< best < ratio * second best in the window
  double min_depth_m = 0.1;             ///< map points nearer than this are not searched
  double max_depth_m = 60;              ///< nor farther ones
  int grid_cell_px = 16;                ///< feature grid cell for window searches
  /// Which map points are projected each frame ("the current map", docs/REGISTRATION.md): true,
  /// ORB-SLAM's local map around the points the previous frame matched (covisibility.hpp);
  /// false, the whole map every frame.
  bool local_map = true;
  int covisibility_min_shared = 15;          ///< ORB-SLAM's covisibility edge threshold
  std::size_t local_map_neighbours = 10;     ///< best covisible keyframes looked at per keyframe
  std::size_t local_map_max_keyframes = 80;  ///< ORB-SLAM's bound on the local keyframes

  /// A frame is registered when the last refinement keeps at least this many inliers; tracking
  /// below it falls back to relocalization.
  int min_inliers = 20;
  /// Predict the pose by constant velocity (else: the previous pose).
  bool constant_velocity = true;

  LocalMapOptions local_map_options() const {
    return {covisibility_min_shared, local_map_neighbours, local_map_max_keyframes};
  }

  /// Every option once: key, unit, accepted values and a line of doc; validate() and to_json()
  /// come from it.
  static const FieldList<RegistrationOptions>& fields();
  /// Throws InputError "registration.<key>: expected ..., got ..." for the first bad option.
  void validate() const;
  nlohmann::json to_json() const;
};

}  // namespace edx::backend::registration
