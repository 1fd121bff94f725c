#include "workloads/backend/registration/registration_backend.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <unordered_map>

namespace edx::backend::registration {
namespace {

/// Best and second-best descriptor distance of one query over a set of candidates.
struct BestTwo {
  int best = std::numeric_limits<int>::max();
  int second = std::numeric_limits<int>::max();
  std::size_t index = 0;
  void offer(int distance, std::size_t i) {
    if (distance < best) {
      second = best;
      best = distance;
      index = i;
    } else if (distance < second) {
      second = distance;
    }
  }
  /// best <= max_distance and best < ratio * second (or no second candidate).
  bool accept(int max_distance, double ratio) const {
    if (best > max_distance) return false;
    return second == std::numeric_limits<int>::max() ||
           static_cast<double>(best) < ratio * static_cast<double>(second);
  }
};

/// One match proposal: a frame feature, a map point and their descriptor distance.
struct Proposal {
  std::size_t feature = 0;
  std::size_t point = 0;
  int distance = 0;
};

/// Keeps, for every feature and for every map point, only the proposal of smallest distance
/// (ties: the earlier proposal), so each is matched at most once.
std::vector<Proposal> unique_matches(std::vector<Proposal> proposals) {
  std::stable_sort(proposals.begin(), proposals.end(),
                   [](const Proposal& a, const Proposal& b) { return a.distance < b.distance; });
  std::unordered_map<std::size_t, bool> feature_used, point_used;
  std::vector<Proposal> kept;
  for (const Proposal& p : proposals) {
    if (feature_used[p.feature] || point_used[p.point]) continue;
    feature_used[p.feature] = point_used[p.point] = true;
    kept.push_back(p);
  }
  std::sort(kept.begin(), kept.end(),
            [](const Proposal& a, const Proposal& b) { return a.feature < b.feature; });
  return kept;
}

Eigen::Isometry3d inverse(const Eigen::Isometry3d& T) { return T.inverse(); }

}  // namespace

RegistrationBackend::RegistrationBackend(const BackendCamera& camera,
                                         const RegistrationOptions& options,
                                         std::shared_ptr<const slam::Map> map,
                                         std::shared_ptr<const bow::Vocabulary> vocabulary)
    : camera_(camera), options_(options), map_(std::move(map)), vocabulary_(std::move(vocabulary)) {
  options_.validate();
  if (!(camera_.fx > 0 && camera_.fy > 0 && camera_.width > 0 && camera_.height > 0)) {
    throw std::runtime_error("registration backend: invalid camera (fx, fy, size must be > 0)");
  }
  if (!map_) throw std::runtime_error("registration backend: no map given");
  if (map_->keyframes.empty())
    throw std::runtime_error("registration backend: map has no keyframes");
  if (map_->landmarks.empty())
    throw std::runtime_error("registration backend: map has no landmarks");
  if (!vocabulary_ || vocabulary_->empty()) {
    throw std::runtime_error("registration backend: no vocabulary (or an empty one) given");
  }
  const std::size_t M = map_->landmarks.size();
  points_.resize(4, static_cast<Eigen::Index>(M));
  point_descriptors_.resize(M);
  std::unordered_map<std::int64_t, std::size_t> keyframe_index;
  for (std::size_t k = 0; k < map_->keyframes.size(); ++k)
    keyframe_index[map_->keyframes[k].id] = k;
  keypoint_points_.resize(map_->keyframes.size());
  keypoint_descriptors_.resize(map_->keyframes.size());
  for (std::size_t k = 0; k < map_->keyframes.size(); ++k) {
    keypoint_points_[k].assign(map_->keyframes[k].keypoints.size(), -1);
  }
  for (std::size_t i = 0; i < M; ++i) {
    const slam::MapLandmark& l = map_->landmarks[i];
    points_.col(static_cast<Eigen::Index>(i)) << l.position, 1.0;
    point_descriptors_[i] = bow::pack(l.descriptor);
    for (const slam::MapObservation& o : l.observations) {
      const auto it = keyframe_index.find(o.keyframe_id);
      if (it == keyframe_index.end() || o.keypoint_index >= keypoint_points_[it->second].size()) {
        continue;  // load_map checks references; a hand-built map may not
      }
      keypoint_points_[it->second][o.keypoint_index] = static_cast<std::ptrdiff_t>(i);
    }
  }
  // The keyframe database: one image per map keyframe, in map order.
  for (std::size_t k = 0; k < map_->keyframes.size(); ++k) {
    std::vector<bow::Descriptor> descriptors;
    for (const slam::MapKeypoint& p : map_->keyframes[k].keypoints) {
      descriptors.push_back(p.descriptor);
      keypoint_descriptors_[k].push_back(bow::pack(p.descriptor));
    }
    bow::BowVector bow;
    bow::FeatureVector features;
    vocabulary_->transform(descriptors, options_.direct_index_level, bow, features);
    database_.add(bow, std::move(features));
  }
  covisibility_ = std::make_unique<CovisibilityGraph>(*map_, options_.local_map_options());
}

std::vector<std::size_t> RegistrationBackend::current_map(
    const std::vector<std::size_t>& anchor_points) {
  auto k = recorder_.kernel("local_map");
  std::vector<std::size_t> points;
  std::size_t keyframes = 0;
  if (options_.local_map) {
    LocalMap local = covisibility_->local_map(anchor_points);
    keyframes = local.keyframes.size();
    points = std::move(local.points);
  } else {
    keyframes = map_->keyframes.size();
    points.resize(static_cast<std::size_t>(points_.cols()));
    for (std::size_t i = 0; i < points.size(); ++i) points[i] = i;
  }
  k.record().m = static_cast<std::int64_t>(anchor_points.size());
  k.record().n = static_cast<std::int64_t>(keyframes);
  k.record().k = static_cast<std::int64_t>(points.size());
  return points;
}

double RegistrationBackend::sigma_px(int octave) const {
  return std::pow(options_.octave_scale, std::max(0, octave));
}

BackendOutput RegistrationBackend::process(const BackendInput& input) {
  if (input.frontend == nullptr)
    throw std::runtime_error("registration backend: no frontend frame");
  ++statistics_.frames;
  const std::vector<frontend::Feature>& features = input.frontend->features;
  Attempt attempt;
  bool tracked = false;
  if (features.empty()) {
    attempt.reason = "no_features";
  } else if (last_T_cam_world_) {
    // Constant velocity: T_k = (T_{k-1} T_{k-2}^-1) T_{k-1}.
    Eigen::Isometry3d guess = *last_T_cam_world_;
    if (options_.constant_velocity && previous_T_cam_world_) {
      guess = *last_T_cam_world_ * inverse(*previous_T_cam_world_) * *last_T_cam_world_;
    }
    const std::vector<std::size_t> points = current_map(last_inlier_points_);
    attempt = track_by_projection(features, guess, options_.tracking_radius_px, points);
    if (!attempt.ok) {
      attempt = track_by_projection(features, guess, 2 * options_.tracking_radius_px, points);
    }
    tracked = attempt.ok;
    if (!attempt.ok) attempt = relocalize(features);
  } else {
    attempt = relocalize(features);
  }

  BackendOutput output;
  if (attempt.ok) {
    ++statistics_.registered;
    ++(tracked ? statistics_.tracked : statistics_.relocalized);
    previous_T_cam_world_ = last_T_cam_world_;
    last_T_cam_world_ = attempt.T_cam_world;
    last_inlier_points_ = std::move(attempt.inlier_points);
    // T_world_body = T_world_cam T_cam_body = T_cam_world^-1 T_body_left^-1.
    output.T_world_body = inverse(attempt.T_cam_world) * inverse(camera_.T_body_left);
    output.status = "ok";
  } else {
    ++statistics_.failures;
    last_T_cam_world_.reset();
    previous_T_cam_world_.reset();
    last_inlier_points_.clear();
    output.status = "registration_failed: " + attempt.reason;
  }
  output.kernels = recorder_.take();
  return output;
}

std::vector<Correspondence> RegistrationBackend::match_by_projection(
    const std::vector<frontend::Feature>& features, const Eigen::Isometry3d& T_cam_world,
    double radius_px, const std::vector<std::size_t>& points) {
  const Eigen::Index M = static_cast<Eigen::Index>(points.size());
  Eigen::Matrix4Xd X(4, M);  // the current map's homogeneous points
  for (Eigen::Index i = 0; i < M; ++i) X.col(i) = points_.col(static_cast<Eigen::Index>(points[i]));
  struct Visible {
    std::size_t point;
    double u, v;
  };
  std::vector<Visible> visible;
  {
    // The accelerable kernel of Table I: Y = C X for the M points of the current map, then
    // u = Y0/Y2, v = Y1/Y2.
    auto k = recorder_.kernel("projection", /*accelerable=*/true);
    const Eigen::Matrix<double, 3, 4> C = camera_matrix(camera_, T_cam_world);
    const Eigen::Matrix3Xd Y = recorder_.op(trace::Op::Gemm, 3, M, 4, 0,
                                            [&] { return project(C, X, options_.precision); });
    for (Eigen::Index i = 0; i < M; ++i) {
      const double z = Y(2, i);
      if (!(z >= options_.min_depth_m && z <= options_.max_depth_m)) continue;
      const double u = Y(0, i) / z, v = Y(1, i) / z;
      if (u < 0 || v < 0 || u >= camera_.width || v >= camera_.height) continue;
      visible.push_back({points[static_cast<std::size_t>(i)], u, v});
    }
    k.record().m = M;
    k.record().n = static_cast<std::int64_t>(visible.size());
    k.record().detail_json = nlohmann::json{{"visible", visible.size()}}.dump();
  }
  auto k = recorder_.kernel("projection_matching");
  // Features bucketed in a grid of cell x cell px for the window searches.
  const int cell = options_.grid_cell_px;
  const int cols = (camera_.width + cell - 1) / cell, rows = (camera_.height + cell - 1) / cell;
  std::vector<std::vector<std::size_t>> grid(static_cast<std::size_t>(cols * rows));
  std::vector<bow::PackedDescriptor> descriptors(features.size());
  for (std::size_t f = 0; f < features.size(); ++f) {
    descriptors[f] = bow::pack(features[f].descriptor);
    const int cx = std::clamp(static_cast<int>(features[f].left.x) / cell, 0, cols - 1);
    const int cy = std::clamp(static_cast<int>(features[f].left.y) / cell, 0, rows - 1);
    grid[static_cast<std::size_t>(cy * cols + cx)].push_back(f);
  }
  std::int64_t comparisons = 0;
  std::vector<Proposal> proposals;
  const double r2 = radius_px * radius_px;
  for (const Visible& p : visible) {
    BestTwo best;
    const int x0 = std::max(0, static_cast<int>((p.u - radius_px) / cell));
    const int x1 = std::min(cols - 1, static_cast<int>((p.u + radius_px) / cell));
    const int y0 = std::max(0, static_cast<int>((p.v - radius_px) / cell));
    const int y1 = std::min(rows - 1, static_cast<int>((p.v + radius_px) / cell));
    for (int gy = y0; gy <= y1; ++gy) {
      for (int gx = x0; gx <= x1; ++gx) {
        for (const std::size_t f : grid[static_cast<std::size_t>(gy * cols + gx)]) {
          const double du = features[f].left.x - p.u, dv = features[f].left.y - p.v;
          if (du * du + dv * dv > r2) continue;
          ++comparisons;
          best.offer(bow::hamming_distance(descriptors[f], point_descriptors_[p.point]), f);
        }
      }
    }
    if (best.accept(options_.projection_max_hamming, options_.projection_ratio)) {
      proposals.push_back({best.index, p.point, best.best});
    }
  }
  std::vector<Correspondence> correspondences;
  for (const Proposal& m : unique_matches(std::move(proposals))) {
    Correspondence c;
    c.world = points_.col(static_cast<Eigen::Index>(m.point)).head<3>();
    c.pixel = Eigen::Vector2d(features[m.feature].left.x, features[m.feature].left.y);
    c.sigma_px = sigma_px(features[m.feature].octave);
    c.landmark = m.point;
    c.feature = m.feature;
    correspondences.push_back(c);
  }
  k.record().m = static_cast<std::int64_t>(visible.size());
  k.record().n = static_cast<std::int64_t>(features.size());
  k.record().k = static_cast<std::int64_t>(correspondences.size());
  k.record().detail_json =
      nlohmann::json{{"comparisons", comparisons}, {"radius_px", radius_px}}.dump();
  return correspondences;
}

RefinementResult RegistrationBackend::refine(const std::vector<Correspondence>& correspondences,
                                             const Eigen::Isometry3d& T_cam_world) {
  auto k = recorder_.kernel("pose_refinement");
  RefinementResult result = refine_pose(camera_, correspondences, T_cam_world, options_);
  k.record().m = static_cast<std::int64_t>(correspondences.size());
  k.record().n = result.inliers;
  k.record().detail_json =
      nlohmann::json{{"iterations", result.iterations}, {"rms_px", result.rms_px}}.dump();
  return result;
}

RegistrationBackend::Attempt RegistrationBackend::track_by_projection(
    const std::vector<frontend::Feature>& features, const Eigen::Isometry3d& T_cam_world_guess,
    double radius_px, const std::vector<std::size_t>& points) {
  Attempt attempt;
  const std::vector<Correspondence> matches =
      match_by_projection(features, T_cam_world_guess, radius_px, points);
  if (static_cast<int>(matches.size()) < options_.min_inliers) {
    attempt.reason = "few_matches";
    return attempt;
  }
  const RefinementResult refined = refine(matches, T_cam_world_guess);
  attempt.inliers = refined.inliers;
  attempt.T_cam_world = refined.T_cam_world;
  if (refined.inliers < options_.min_inliers) {
    attempt.reason = "few_inliers";
    return attempt;
  }
  for (std::size_t c = 0; c < matches.size(); ++c) {
    if (refined.inlier[c]) attempt.inlier_points.push_back(matches[c].landmark);
  }
  attempt.ok = true;
  return attempt;
}

RegistrationBackend::Attempt RegistrationBackend::relocalize(
    const std::vector<frontend::Feature>& features) {
  ++statistics_.relocalization_attempts;
  Attempt attempt;
  std::vector<bow::PackedDescriptor> descriptors(features.size());
  for (std::size_t f = 0; f < features.size(); ++f)
    descriptors[f] = bow::pack(features[f].descriptor);

  std::vector<bow::QueryResult> candidates;
  bow::FeatureVector frame_nodes;
  {
    auto k = recorder_.kernel("bow_query");
    std::vector<bow::Descriptor> raw;
    raw.reserve(features.size());
    for (const frontend::Feature& f : features) raw.push_back(f.descriptor);
    bow::BowVector bow;
    vocabulary_->transform(raw, options_.direct_index_level, bow, frame_nodes);
    bow::QueryStats stats;
    candidates = database_.query(bow, options_.bow_candidates, &stats);
    k.record().m = static_cast<std::int64_t>(features.size());
    k.record().n = static_cast<std::int64_t>(candidates.size());
    k.record().detail_json = nlohmann::json{
        {"words", stats.words},
        {"postings", stats.postings},
        {"database_candidates", stats.candidates},
        {"keyframes",
         database_.size()}}.dump();
  }
  if (candidates.empty()) {
    attempt.reason = "no_candidates";
    return attempt;
  }

  // Matching: per candidate keyframe, features and keypoints under the same vocabulary node.
  std::vector<std::vector<Correspondence>> per_candidate(candidates.size());
  {
    auto k = recorder_.kernel("matching");
    std::int64_t comparisons = 0, total = 0;
    for (std::size_t c = 0; c < candidates.size(); ++c) {
      const std::size_t kf = candidates[c].image;
      const bow::FeatureVector& kf_nodes = database_.features(static_cast<bow::ImageId>(kf));
      std::vector<Proposal> proposals;
      auto fi = frame_nodes.begin();
      auto ki = kf_nodes.begin();
      while (fi != frame_nodes.end() && ki != kf_nodes.end()) {
        if (fi->first < ki->first) {
          ++fi;
        } else if (ki->first < fi->first) {
          ++ki;
        } else {
          for (const std::uint32_t f : fi->second) {
            BestTwo best;
            for (const std::uint32_t p : ki->second) {
              if (keypoint_points_[kf][p] < 0) continue;
              ++comparisons;
              best.offer(bow::hamming_distance(descriptors[f], keypoint_descriptors_[kf][p]), p);
            }
            if (best.accept(options_.bow_max_hamming, options_.bow_ratio)) {
              proposals.push_back(
                  {f, static_cast<std::size_t>(keypoint_points_[kf][best.index]), best.best});
            }
          }
          ++fi;
          ++ki;
        }
      }
      for (const Proposal& m : unique_matches(std::move(proposals))) {
        Correspondence corr;
        corr.world = points_.col(static_cast<Eigen::Index>(m.point)).head<3>();
        corr.pixel = Eigen::Vector2d(features[m.feature].left.x, features[m.feature].left.y);
        corr.sigma_px = sigma_px(features[m.feature].octave);
        corr.landmark = m.point;
        corr.feature = m.feature;
        per_candidate[c].push_back(corr);
      }
      total += static_cast<std::int64_t>(per_candidate[c].size());
    }
    k.record().m = static_cast<std::int64_t>(candidates.size());
    k.record().n = total;
    k.record().detail_json = nlohmann::json{{"comparisons", comparisons}}.dump();
  }

  // PnP per candidate with enough matches; the one with most inliers wins (ties: better score).
  std::optional<PnpResult> best_pnp;
  std::size_t best_candidate = 0;
  bool any_matches = false;
  for (std::size_t c = 0; c < candidates.size(); ++c) {
    if (static_cast<int>(per_candidate[c].size()) < options_.pnp_min_matches) continue;
    any_matches = true;
    auto k = recorder_.kernel("pnp");
    PnpResult pnp = solve_pnp_ransac(camera_, per_candidate[c], options_);
    k.record().m = static_cast<std::int64_t>(per_candidate[c].size());
    k.record().n = static_cast<std::int64_t>(pnp.inliers.size());
    if (pnp.ok && (!best_pnp || pnp.inliers.size() > best_pnp->inliers.size())) {
      best_pnp = std::move(pnp);
      best_candidate = c;
    }
  }
  if (!any_matches) {
    attempt.reason = "few_matches";
    return attempt;
  }
  if (!best_pnp) {
    attempt.reason = "pnp_failed";
    return attempt;
  }
  const RefinementResult refined = refine(per_candidate[best_candidate], best_pnp->T_cam_world);
  if (refined.inliers < options_.pnp_min_inliers) {
    attempt.reason = "few_inliers";
    return attempt;
  }
  // Use the current map around the PnP inliers: tracking by projection in a narrow window.
  std::vector<std::size_t> anchors;
  for (std::size_t c = 0; c < per_candidate[best_candidate].size(); ++c) {
    if (refined.inlier[c]) anchors.push_back(per_candidate[best_candidate][c].landmark);
  }
  return track_by_projection(features, refined.T_cam_world, options_.relocalization_radius_px,
                             current_map(anchors));
}

std::unique_ptr<Backend> make_registration_backend(
    const datasets::Dataset& dataset, const RegistrationOptions& options,
    std::shared_ptr<const slam::Map> map, std::shared_ptr<const bow::Vocabulary> vocabulary) {
  return std::make_unique<RegistrationBackend>(BackendCamera::from(dataset.calibration()), options,
                                               std::move(map), std::move(vocabulary));
}

}  // namespace edx::backend::registration
