#include "workloads/eval/association.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <stdexcept>
#include <tuple>

namespace edx::eval {
namespace {

void require_poses(const Trajectory& gt, const Trajectory& est) {
  for (const Trajectory* trajectory : {&gt, &est}) {
    if (trajectory->poses.empty()) {
      throw std::runtime_error(fmt::format("{}: no poses", trajectory->source));
    }
  }
}

}  // namespace

Association associate_by_frame_index(const Trajectory& gt, const Trajectory& est) {
  require_poses(gt, est);
  Association association;
  std::size_t g = 0;
  for (std::size_t e = 0; e < est.poses.size(); ++e) {
    const auto index = est.poses[e].frame_index;
    while (g < gt.poses.size() && gt.poses[g].frame_index < index) ++g;
    if (g < gt.poses.size() && gt.poses[g].frame_index == index) {
      association.pairs.push_back({g, e});
    } else {
      ++association.est_unmatched;
    }
  }
  if (association.pairs.empty()) {
    throw std::runtime_error(
        fmt::format("no frame index of {} (frames {}..{}) is in {} ({}..{})", est.source,
                    est.poses.front().frame_index, est.poses.back().frame_index, gt.source,
                    gt.poses.front().frame_index, gt.poses.back().frame_index));
  }
  return association;
}

Association associate_by_time(const Trajectory& gt, const Trajectory& est, double t_max_diff_s) {
  if (!(t_max_diff_s >= 0.0) || !std::isfinite(t_max_diff_s)) {
    throw std::runtime_error(fmt::format(
        "t_max_diff must be a finite non-negative number of seconds, got {}", t_max_diff_s));
  }
  require_poses(gt, est);
  const double gt_begin = gt.poses.front().time_s, gt_end = gt.poses.back().time_s;
  const double est_begin = est.poses.front().time_s, est_end = est.poses.back().time_s;
  if (est_end < gt_begin - t_max_diff_s || est_begin > gt_end + t_max_diff_s) {
    throw std::runtime_error(fmt::format(
        "no overlap in time: {} covers [{:.9f}, {:.9f}] s, {} covers [{:.9f}, {:.9f}] s", gt.source,
        gt_begin, gt_end, est.source, est_begin, est_end));
  }

  // Every candidate (|dt|, est, gt) within tolerance; both trajectories are sorted by time.
  std::vector<std::tuple<double, std::size_t, std::size_t>> candidates;
  std::size_t first_gt = 0;
  for (std::size_t e = 0; e < est.poses.size(); ++e) {
    const double t = est.poses[e].time_s;
    while (first_gt < gt.poses.size() && gt.poses[first_gt].time_s < t - t_max_diff_s) ++first_gt;
    for (std::size_t g = first_gt; g < gt.poses.size() && gt.poses[g].time_s <= t + t_max_diff_s;
         ++g) {
      candidates.emplace_back(std::abs(gt.poses[g].time_s - t), e, g);
    }
  }
  std::sort(candidates.begin(), candidates.end());

  std::vector<bool> gt_used(gt.poses.size(), false), est_used(est.poses.size(), false);
  Association association;
  for (const auto& [dt, e, g] : candidates) {
    if (est_used[e] || gt_used[g]) continue;
    est_used[e] = gt_used[g] = true;
    association.pairs.push_back({g, e});
  }
  std::sort(association.pairs.begin(), association.pairs.end(),
            [](const PosePair& a, const PosePair& b) { return a.est < b.est; });
  association.est_unmatched = est.poses.size() - association.pairs.size();
  if (association.pairs.empty()) {
    throw std::runtime_error(fmt::format("no pose of {} is within {} s of a pose of {}", est.source,
                                         t_max_diff_s, gt.source));
  }
  return association;
}

Association associate(const Trajectory& gt, const Trajectory& est, double t_max_diff_s) {
  if (gt.stamp_kind != est.stamp_kind) {
    throw std::runtime_error(fmt::format(
        "{} and {} are stamped differently (frame indices vs timestamps)", gt.source, est.source));
  }
  return gt.stamp_kind == StampKind::kFrameIndex ? associate_by_frame_index(gt, est)
                                                 : associate_by_time(gt, est, t_max_diff_s);
}

}  // namespace edx::eval
