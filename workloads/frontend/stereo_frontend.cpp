#include "workloads/frontend/stereo_frontend.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cstring>
#include <exception>
#include <functional>
#include <initializer_list>
#include <numeric>
#include <opencv2/core/utility.hpp>
#include <stdexcept>

#include "workloads/frontend/task_timer.hpp"

namespace edx::frontend {
namespace {

using trace::Image;
using trace::Task;

constexpr int kMinImageSide = 64;

void check_image(const cv::Mat& image, const char* side, std::size_t frame) {
  if (image.empty()) {
    throw std::runtime_error(fmt::format("frame {}: {} image is empty", frame, side));
  }
  if (image.type() != CV_8UC1) {
    throw std::runtime_error(
        fmt::format("frame {}: {} image has {} channel(s) of depth {} (expected 8-bit grayscale)",
                    frame, side, image.channels(), image.depth()));
  }
}

/// Runs `jobs` concurrently on OpenCV's thread pool (cv::parallel_for_, one stripe per job,
/// cv::getNumThreads() threads), waits for all and rethrows the first job's exception. OpenCV
/// runs parallel_for_ calls made inside a running one serially, so the OpenCV functions the
/// jobs call (LK, Gaussian filter, resize) do not compete with the jobs for the cores.
/// Returns the jobs' work: the sum of each job's thread CPU time, ns (the pool's threads waiting
/// for work, and the calling thread waiting for the jobs, are not work).
std::int64_t run_concurrently(std::initializer_list<std::function<void()>> jobs) {
  const std::vector<std::function<void()>> list(jobs);
  std::vector<std::exception_ptr> failures(list.size());
  std::vector<std::int64_t> work_ns(list.size(), 0);
  cv::parallel_for_(
      cv::Range(0, static_cast<int>(list.size())),
      [&](const cv::Range& range) {
        for (int j = range.start; j < range.end; ++j) {
          const auto index = static_cast<std::size_t>(j);
          const std::int64_t start = trace::thread_cpu_ns();
          try {
            list[index]();
          } catch (...) {
            failures[index] = std::current_exception();
          }
          work_ns[index] = trace::thread_cpu_ns() - start;
        }
      },
      static_cast<double>(list.size()));
  for (const std::exception_ptr& failure : failures) {
    if (failure) std::rethrow_exception(failure);
  }
  return std::accumulate(work_ns.begin(), work_ns.end(), std::int64_t{0});
}

/// The CPU time of a frame's work (FrontendFrame::host_ns): the calling thread's CPU time,
/// except while it waits in run_concurrently, plus the concurrent jobs' own CPU time.
class FrameWorkClock {
 public:
  FrameWorkClock() : start_ns_(trace::thread_cpu_ns()) {}
  /// Runs `jobs` concurrently and counts their work instead of the caller's wait.
  void run_concurrently(std::initializer_list<std::function<void()>> jobs) {
    const std::int64_t before = trace::thread_cpu_ns();
    jobs_ns_ += edx::frontend::run_concurrently(jobs);
    waited_ns_ += trace::thread_cpu_ns() - before;
  }
  std::int64_t elapsed_ns() const {
    return trace::thread_cpu_ns() - start_ns_ - waited_ns_ + jobs_ns_;
  }

 private:
  std::int64_t start_ns_;
  std::int64_t waited_ns_ = 0, jobs_ns_ = 0;
};

}  // namespace

StereoFrontend::StereoFrontend(const FrontendOptions& options, const StereoCamera& camera)
    : options_((options.validate(), options)),
      camera_(camera),
      extractor_(options),
      matcher_(options),
      tracker_(options) {
  if (!(camera.fx > 0) || !(camera.baseline_m > 0)) {
    throw std::runtime_error(
        fmt::format("stereo camera fx = {} px, baseline = {} m (expected both > 0)", camera.fx,
                    camera.baseline_m));
  }
}

void StereoFrontend::reset() {
  image_size_.reset();
  previous_pyramid_ = LkPyramid{};
  previous_points_.clear();
  previous_tracks_.clear();
}

FrontendFrame StereoFrontend::process(const cv::Mat& left, const cv::Mat& right) {
  FrameWorkClock clock;
  const std::size_t frame = frames_;
  check_image(left, "left", frame);
  check_image(right, "right", frame);
  if (left.size() != right.size()) {
    throw std::runtime_error(fmt::format("frame {}: left image is {}x{} but right is {}x{}", frame,
                                         left.cols, left.rows, right.cols, right.rows));
  }
  if (left.cols < kMinImageSide || left.rows < kMinImageSide) {
    throw std::runtime_error(fmt::format("frame {}: images are {}x{} (expected at least {}x{})",
                                         frame, left.cols, left.rows, kMinImageSide,
                                         kMinImageSide));
  }
  if (image_size_ && *image_size_ != left.size()) {
    throw std::runtime_error(
        fmt::format("frame {}: images are {}x{} but the sequence started at {}x{}", frame,
                    left.cols, left.rows, image_size_->width, image_size_->height));
  }
  image_size_ = left.size();

  trace::TaskRecord fd_left = make_task(Task::FD, Image::Left);
  trace::TaskRecord if_left = make_task(Task::IF, Image::Left);
  trace::TaskRecord fd_right = make_task(Task::FD, Image::Right);
  trace::TaskRecord if_right = make_task(Task::IF, Image::Right);
  trace::TaskRecord dc = make_task(Task::DC, Image::Left);
  trace::TaskRecord lss = make_task(Task::LSS, Image::Left);
  trace::TaskRecord fc_left = make_task(Task::FC, Image::Left);
  trace::TaskRecord fc_right = make_task(Task::FC, Image::Right);
  trace::TaskRecord mo = make_task(Task::MO, Image::Stereo);
  trace::TaskRecord dr = make_task(Task::DR, Image::Stereo);

  // Stage 1, three independent chains: temporal matching of the left image (DC, LSS; the
  // longest, started first), the left image's detection and filtering (FD L, IF L) and the
  // right image's (FD R, IF R). Stage 2: FC R beside the left features' selection and FC L,
  // which need the tracks. With parallel_images each stage's chains share OpenCV's pool.
  std::vector<cv::KeyPoint> right_keypoints;
  ImagePyramid right_smoothed;
  DetectedCorners right_corners;
  auto right_detection = [&] {
    right_corners = extractor_.detect(right, fd_right);
    right_keypoints = extractor_.select(right_corners, {}, options_.right_features_per_image,
                                        options_.right_min_feature_distance_px, fd_right);
    right_smoothed = extractor_.smooth(right_corners.pyramid, if_right);
  };
  DetectedCorners left_corners;
  ImagePyramid left_smoothed;
  auto left_detection = [&] {
    left_corners = extractor_.detect(left, fd_left);
    left_smoothed = extractor_.smooth(left_corners.pyramid, if_left);
  };
  LkPyramid pyramid;
  TrackResult tracks;
  auto tracking_chain = [&] {
    pyramid = tracker_.build_pyramid(left, dc);
    dc.points = static_cast<std::int64_t>(previous_points_.size());
    tracks = tracker_.track(previous_pyramid_, pyramid, previous_points_, lss);
  };
  cv::Mat right_descriptors;
  auto right_description = [&] {
    right_descriptors =
        extractor_.describe(right_corners.pyramid, right_smoothed, right_keypoints, fc_right);
  };
  if (options_.parallel_images) {
    clock.run_concurrently({tracking_chain, left_detection, right_detection});
  } else {
    right_detection();
    left_detection();
    tracking_chain();
  }

  FrontendFrame out;
  out.index = frame;
  // Tracked features keep id and octave; a track ends when LK fails, the round trip is off
  // or the point comes too close to the border for a descriptor at its octave.
  std::vector<cv::KeyPoint> left_keypoints;
  std::vector<Track> tracks_now;
  std::vector<std::pair<float, float>> match_quality;  // tracks' (LK residual, round trip)
  std::vector<cv::Point2f> occupied;
  for (std::size_t i = 0; i < previous_tracks_.size(); ++i) {
    const Track& t = previous_tracks_[i];
    const cv::Point2f p = tracks.positions[i];
    if (!tracks.tracked[i] || !extractor_.describable(left_corners.pyramid, p, t.octave)) {
      ++out.stats.lost;
      continue;
    }
    const float scale =
        static_cast<float>(left_corners.pyramid.scales[static_cast<std::size_t>(t.octave)]);
    left_keypoints.emplace_back(p, kOrbPatchSize * scale, -1.f, t.response, t.octave);
    tracks_now.push_back({t.id, t.age + 1, t.octave, t.response});
    match_quality.emplace_back(tracks.lk_residual[i], tracks.round_trip_px[i]);
    occupied.push_back(p);
  }
  out.stats.tracked = static_cast<int>(tracks_now.size());
  // New features fill the budget away from the tracks.
  const int budget = options_.features_per_image - static_cast<int>(tracks_now.size());
  for (const cv::KeyPoint& k : extractor_.select(left_corners, occupied, budget,
                                                 options_.min_feature_distance_px, fd_left)) {
    left_keypoints.push_back(k);
    tracks_now.push_back({next_id_++, 0, k.octave, k.response});
  }
  out.stats.new_features = static_cast<int>(tracks_now.size()) - out.stats.tracked;

  cv::Mat left_descriptors;
  auto left_description = [&] {
    left_descriptors =
        extractor_.describe(left_corners.pyramid, left_smoothed, left_keypoints, fc_left);
  };
  if (options_.parallel_images) {
    clock.run_concurrently({left_description, right_description});
  } else {
    right_description();
    left_description();
  }
  std::vector<StereoMatch> matches =
      matcher_.match(left_keypoints, left_descriptors, right_keypoints, right_descriptors, mo);
  matcher_.refine(left, right, left_keypoints, right_keypoints, matches, dr);

  out.features.resize(left_keypoints.size());
  for (std::size_t i = 0; i < left_keypoints.size(); ++i) {
    Feature& f = out.features[i];
    const cv::KeyPoint& k = left_keypoints[i];
    f.id = tracks_now[i].id;
    f.age = tracks_now[i].age;
    f.octave = k.octave;
    if (i < match_quality.size()) {  // the tracks come first in left_keypoints
      f.lk_residual = match_quality[i].first;
      f.round_trip_px = match_quality[i].second;
    }
    f.left = k.pt;
    f.angle = k.angle;
    f.response = k.response;
    std::memcpy(f.descriptor.data(), left_descriptors.ptr<uchar>(static_cast<int>(i)),
                f.descriptor.size());
    const StereoMatch& m = matches[i];
    if (m.valid) {
      f.stereo = true;
      f.right = cv::Point2f(m.right_x, k.pt.y);
      f.disparity = m.disparity;
      f.depth_m = camera_.fx * camera_.baseline_m / m.disparity;
      f.hamming = m.hamming;
      ++out.stats.stereo_matches;
    }
  }
  out.stats.left_keypoints = static_cast<int>(left_keypoints.size());
  out.stats.right_keypoints = static_cast<int>(right_keypoints.size());

  out.tasks = {fd_left, if_left, fd_right, if_right, dc, lss, fc_left, fc_right, mo, dr};
  out.host_ns = clock.elapsed_ns();
  // Counting LK iterations is measurement, not frontend work: after the frame's timing.
  if (options_.count_lk_iterations) {
    tracker_.count_iterations(previous_pyramid_, pyramid, previous_points_, tracks, out.tasks[5]);
  }

  previous_pyramid_ = std::move(pyramid);
  previous_points_.clear();
  for (const cv::KeyPoint& k : left_keypoints) previous_points_.push_back(k.pt);
  previous_tracks_ = std::move(tracks_now);
  ++frames_;
  return out;
}

}  // namespace edx::frontend
