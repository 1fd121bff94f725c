#include "workloads/frontend/temporal_tracker.hpp"

#include <cmath>
#include <opencv2/video/tracking.hpp>
#include <stdexcept>

#include "workloads/frontend/task_timer.hpp"

namespace edx::frontend {
namespace {

/// Level `level` of a pyramid alone: [image, derivatives], still padded (an ROI of the level's
/// buffer), which calcOpticalFlowPyrLK accepts as a one-level pyramid.
std::vector<cv::Mat> single_level(const LkPyramid& pyramid, int level) {
  const auto index = static_cast<std::size_t>(2 * level);
  return {pyramid.mats[index], pyramid.mats[index + 1]};
}

}  // namespace

void run_lk(const LkPyramid& from, const LkPyramid& to, const std::vector<cv::Point2f>& points,
            const LkCall& call, std::vector<cv::Point2f>& positions,
            std::vector<unsigned char>& status, std::vector<float>* error_out) {
  std::vector<float> local;
  std::vector<float>& error = error_out ? *error_out : local;
  cv::calcOpticalFlowPyrLK(from.mats, to.mats, points, positions, status, error, call.window,
                           call.max_level, call.criteria, 0, call.min_eigen);
}

LkReplay replay_lk(const LkPyramid& from, const LkPyramid& to,
                   const std::vector<cv::Point2f>& points, const LkCall& call) {
  // OpenCV's normalisation of the criteria and the top level (calcOpticalFlowPyrLK).
  const cv::TermCriteria& criteria = call.criteria;
  const int max_count = (criteria.type & cv::TermCriteria::COUNT)
                            ? std::min(std::max(criteria.maxCount, 0), 100)
                            : 30;
  const double epsilon = (criteria.type & cv::TermCriteria::EPS)
                             ? std::min(std::max(criteria.epsilon, 0.0), 10.0)
                             : 0.01;
  const double epsilon_squared = epsilon * epsilon;
  const int max_level = std::min({call.max_level, from.max_level, to.max_level});
  const cv::TermCriteria one_step(cv::TermCriteria::COUNT, 1, epsilon);

  LkReplay replay;
  replay.levels.resize(static_cast<std::size_t>(std::max(max_level + 1, 0)));
  replay.status.assign(points.size(), 1);
  std::vector<cv::Point2f> guess(points.size());
  for (int level = max_level; level >= 0; --level) {
    LkLevelIterations& counts = replay.levels[static_cast<std::size_t>(level)];
    counts.level = level;
    // Same float arithmetic as OpenCV: p * (1 / 2^level), guesses doubled between levels.
    const float to_level = static_cast<float>(1.0 / (1 << level));
    std::vector<cv::Point2f> start(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
      start[i] = points[i] * to_level;
      guess[i] = level == max_level ? start[i] : guess[i] * 2.f;
    }
    const std::vector<cv::Mat> from_level = single_level(from, level);
    const std::vector<cv::Mat> to_level_mats = single_level(to, level);

    std::vector<std::size_t> active(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) active[i] = i;
    std::vector<cv::Point2f> previous_delta(points.size());
    std::vector<cv::Point2f> batch_start, batch_guess;
    std::vector<unsigned char> batch_status;
    std::vector<float> batch_error;
    for (int iteration = 0; iteration < max_count && !active.empty(); ++iteration) {
      batch_start.clear();
      batch_guess.clear();
      for (const std::size_t i : active) {
        batch_start.push_back(start[i]);
        batch_guess.push_back(guess[i]);
      }
      cv::calcOpticalFlowPyrLK(from_level, to_level_mats, batch_start, batch_guess, batch_status,
                               batch_error, call.window, 0, one_step, cv::OPTFLOW_USE_INITIAL_FLOW,
                               call.min_eigen);
      std::vector<std::size_t> still_active;
      for (std::size_t b = 0; b < active.size(); ++b) {
        const std::size_t i = active[b];
        if (!batch_status[b]) {
          // Bounds or eigenvalue check failed before an update: the point leaves this level
          // (and fails for good on level 0), as in OpenCV's loop.
          if (level == 0) replay.status[i] = 0;
          continue;
        }
        if (iteration == 0) ++counts.points;
        ++counts.iterations;
        const cv::Point2f delta = batch_guess[b] - guess[i];
        guess[i] = batch_guess[b];
        if (delta.ddot(delta) <= epsilon_squared) continue;
        if (iteration > 0 && std::abs(delta.x + previous_delta[i].x) < 0.01 &&
            std::abs(delta.y + previous_delta[i].y) < 0.01) {
          guess[i] -= delta * 0.5f;
          continue;
        }
        previous_delta[i] = delta;
        still_active.push_back(i);
      }
      active.swap(still_active);
    }
  }
  replay.positions = guess;
  return replay;
}

LkCall TemporalTracker::forward_call() const {
  LkCall call;
  call.window = cv::Size(options_.lk_window_px, options_.lk_window_px);
  call.max_level = options_.lk_max_level;
  call.criteria = cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS,
                                   options_.lk_max_iterations, options_.lk_epsilon_px);
  call.min_eigen = options_.lk_min_eigen;
  return call;
}

LkPyramid TemporalTracker::build_pyramid(const cv::Mat& image, trace::TaskRecord& dc) const {
  ScopedTaskTimer timer(dc);
  LkPyramid pyramid;
  const cv::Size window(options_.lk_window_px, options_.lk_window_px);
  pyramid.max_level = cv::buildOpticalFlowPyramid(image, pyramid.mats, window,
                                                  options_.lk_max_level, /*withDerivatives=*/true);
  for (int level = 0; level <= pyramid.max_level; ++level) {
    const cv::Mat& img = pyramid.mats[static_cast<std::size_t>(2 * level)];
    const std::int64_t pixels = static_cast<std::int64_t>(img.cols) * img.rows;
    dc.pixels += pixels;
    dc.levels += 1;
    dc.per_level.push_back({level, img.cols, img.rows, pixels, 0, 0});
  }
  dc.window_size = 3;  // Scharr derivative stencil
  return pyramid;
}

TrackResult TemporalTracker::track(const LkPyramid& previous, const LkPyramid& current,
                                   const std::vector<cv::Point2f>& points,
                                   trace::TaskRecord& lss) const {
  TrackResult result;
  result.positions.assign(points.size(), cv::Point2f(-1, -1));
  result.tracked.assign(points.size(), 0);
  result.round_trip_px.assign(points.size(), -1.0f);
  result.lk_residual.assign(points.size(), -1.0f);
  const int max_level = std::min({options_.lk_max_level, previous.max_level, current.max_level});
  lss.levels = max_level + 1;
  lss.window_size = options_.lk_window_px;
  std::vector<trace::LevelWork> per_level(static_cast<std::size_t>(max_level + 1));
  for (int level = 0; level <= max_level; ++level) {
    const cv::Mat& img = current.mats[static_cast<std::size_t>(2 * level)];
    per_level[static_cast<std::size_t>(level)] = {level, img.cols, img.rows, 0, 0, 0};
  }
  if (points.empty() || previous.empty() || current.empty()) {
    lss.per_level = per_level;
    return result;
  }
  const LkCall forward = forward_call();
  LkCall backward = forward;
  backward.max_level = std::min(options_.lk_check_max_level, max_level);
  std::vector<cv::Point2f> forward_points, backward_points, back;
  std::vector<unsigned char> forward_status, backward_status;
  std::vector<std::size_t> converged;
  {
    ScopedTaskTimer timer(lss);
    std::vector<float> forward_residual;
    run_lk(previous, current, points, forward, forward_points, forward_status, &forward_residual);
    for (std::size_t i = 0; i < points.size(); ++i) {
      if (!forward_status[i]) continue;
      result.lk_residual[i] = forward_residual[i];
      converged.push_back(i);
      backward_points.push_back(forward_points[i]);
    }
    if (!backward_points.empty()) {
      run_lk(current, previous, backward_points, backward, back, backward_status);
    }
    for (std::size_t b = 0; b < converged.size(); ++b) {
      const std::size_t i = converged[b];
      result.positions[i] = forward_points[i];
      if (!backward_status[b]) continue;
      const cv::Point2f round_trip = back[b] - points[i];
      result.round_trip_px[i] = static_cast<float>(std::hypot(round_trip.x, round_trip.y));
      result.tracked[i] = result.round_trip_px[i] < options_.fb_threshold_px ? 1 : 0;
    }
    lss.points += static_cast<std::int64_t>(points.size() + converged.size());
  }

  result.backward_from = std::move(backward_points);
  lss.per_level = per_level;
  return result;
}

void TemporalTracker::count_iterations(const LkPyramid& previous, const LkPyramid& current,
                                       const std::vector<cv::Point2f>& points,
                                       const TrackResult& result, trace::TaskRecord& lss) const {
  if (points.empty() || previous.empty() || current.empty()) return;
  const LkCall forward = forward_call();
  LkCall backward = forward;
  backward.max_level = std::min(options_.lk_check_max_level, static_cast<int>(lss.levels) - 1);
  const LkReplay forward_replay = replay_lk(previous, current, points, forward);
  const LkReplay backward_replay = replay_lk(current, previous, result.backward_from, backward);
  for (const LkReplay* replay : {&forward_replay, &backward_replay}) {
    for (const LkLevelIterations& level : replay->levels) {
      trace::LevelWork& work = lss.per_level.at(static_cast<std::size_t>(level.level));
      work.points += level.points;
      work.iterations += level.iterations;
      lss.iterations += level.iterations;
    }
  }
}

}  // namespace edx::frontend
