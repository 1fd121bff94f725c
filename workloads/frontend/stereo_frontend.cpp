#include "workloads/frontend/stereo_frontend.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstring>
#include <exception>
#include <functional>
#include <mutex>
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

/// One job of run_jobs: `run`, started only once job `after` (an earlier index, -1: none) has
/// finished.
struct Job {
  std::function<void()> run;
  int after = -1;
};

/// Runs `jobs` on OpenCV's thread pool: min(cv::getNumThreads(), jobs) workers in one
/// cv::parallel_for_ take the jobs in list order (each the next one not yet taken, so the list
/// should start with the longest), waits for all and rethrows the first job's exception (a job
/// whose `after` failed is skipped). Jobs only ever wait for earlier ones, which some worker
/// has already taken, so a worker never waits forever, whatever the pool does; results do not
/// depend on which worker runs what. OpenCV runs parallel_for_ calls made inside a running one
/// serially, so the OpenCV functions the jobs call (LK, Gaussian filter, resize) do not compete
/// with the jobs for the cores. Returns the jobs' work: the sum of each job's thread CPU time, ns
/// (workers waiting for a job, and the calling thread waiting for the workers, are not work),
/// and their span: the largest CPU time of the jobs one worker ran (JobsWork).
struct JobsWork {
  std::int64_t total_ns = 0, span_ns = 0;
};
JobsWork run_jobs(const std::vector<Job>& jobs) {
  const std::size_t n = jobs.size();
  std::vector<std::exception_ptr> failures(n);
  std::vector<std::int64_t> work_ns(n, 0);
  std::vector<char> finished(n, 0);
  std::mutex mutex;
  std::condition_variable finished_one;
  std::atomic<std::size_t> next{0};
  const int workers = std::max(1, std::min(cv::getNumThreads(), static_cast<int>(n)));
  std::vector<std::int64_t> worker_ns(static_cast<std::size_t>(workers), 0);
  cv::parallel_for_(
      cv::Range(0, workers),
      [&](const cv::Range& range) {
        for (int w = range.start; w < range.end; ++w) {
          for (std::size_t index = next++; index < n; index = next++) {
            const Job& job = jobs[index];
            bool skip = false;
            if (job.after >= 0) {
              const auto after = static_cast<std::size_t>(job.after);
              std::unique_lock<std::mutex> lock(mutex);
              finished_one.wait(lock, [&] { return finished[after] != 0; });
              skip = failures[after] != nullptr;
            }
            const std::int64_t start = trace::thread_cpu_ns();
            std::exception_ptr failure;
            if (!skip) {
              try {
                job.run();
              } catch (...) {
                failure = std::current_exception();
              }
            }
            const std::int64_t end = trace::thread_cpu_ns();
            {
              const std::lock_guard<std::mutex> lock(mutex);
              work_ns[index] = end - start;
              worker_ns[static_cast<std::size_t>(w)] += end - start;
              failures[index] = failure;
              finished[index] = 1;
            }
            finished_one.notify_all();
          }
        }
      },
      static_cast<double>(workers));
  for (const std::exception_ptr& failure : failures) {
    if (failure) std::rethrow_exception(failure);
  }
  return {std::accumulate(work_ns.begin(), work_ns.end(), std::int64_t{0}),
          *std::max_element(worker_ns.begin(), worker_ns.end())};
}

/// The CPU time of a frame's work (FrontendFrame::host_ns): the calling thread's CPU time,
/// except while it waits in run_jobs, plus the jobs' own CPU time; and its span
/// (FrontendFrame::span_ns): the same with each run_jobs counted by its span.
class FrameWorkClock {
 public:
  FrameWorkClock() : start_ns_(trace::thread_cpu_ns()) {}
  /// Runs `jobs` (run_jobs) and counts their work instead of the caller's wait.
  void run_jobs(const std::vector<Job>& jobs) {
    const std::int64_t before = trace::thread_cpu_ns();
    const JobsWork work = edx::frontend::run_jobs(jobs);
    jobs_ns_ += work.total_ns;
    span_ns_ += work.span_ns;
    waited_ns_ += trace::thread_cpu_ns() - before;
  }
  /// The work until `now` (the calling thread's trace::thread_cpu_ns()).
  std::int64_t elapsed_ns(std::int64_t now) const {
    return now - start_ns_ - waited_ns_ + jobs_ns_;
  }
  /// The same with each run_jobs counted by its span.
  std::int64_t span_ns(std::int64_t now) const { return now - start_ns_ - waited_ns_ + span_ns_; }

 private:
  std::int64_t start_ns_;
  std::int64_t waited_ns_ = 0, jobs_ns_ = 0, span_ns_ = 0;
};

/// Contiguous parts LSS's points are split into for the parallel run (a fixed number, so the
/// split does not depend on the threads; LK solves every point on its own, so the parts'
/// results, concatenated, are those of one call on all points).
constexpr std::size_t kTrackParts = 4;

/// FC's levels split into two parts of about equal pixels for the parallel run: levels in order,
/// each to the part with fewer pixels so far (4 levels at scale 1.2: {0, 3} and {1, 2}).
std::array<std::vector<int>, 2> describe_parts(const ImagePyramid& pyramid) {
  std::array<std::vector<int>, 2> parts;
  std::array<std::int64_t, 2> pixels{0, 0};
  for (std::size_t level = 0; level < pyramid.levels.size(); ++level) {
    const std::size_t part = pixels[1] < pixels[0] ? 1 : 0;
    parts[part].push_back(static_cast<int>(level));
    pixels[part] += static_cast<std::int64_t>(pyramid.levels[level].total());
  }
  return parts;
}

/// Adds a part's work to `task`: time and the counts, its per_level rows appended.
void add_part(trace::TaskRecord& task, const trace::TaskRecord& part) {
  task.host_ns += part.host_ns;
  task.pixels += part.pixels;
  task.levels += part.levels;
  task.points += part.points;
  task.per_level.insert(task.per_level.end(), part.per_level.begin(), part.per_level.end());
}

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

  // With parallel_images the stages are cut finer than the chains of the file comment for the
  // cores to share (three chains on two cores leave one idle): stage 1 runs DC, both detection
  // chains and LSS in kTrackParts parts of the points (each after DC); stage 2 runs each
  // image's FC in 2 parts of its pyramid levels; the workers take the jobs in that order. LK
  // solves every point on its own and ORB describes every keypoint on its own level, so the
  // parts' results are those of the whole, and the task rows the same work as without
  // parallel_images (host_ns: the parts' CPU time summed).
  // Stage 1, three independent chains: temporal matching of the left image (DC, LSS; the
  // longest, started first), the left image's detection and filtering (FD L, IF L) and the
  // right image's (FD R, IF R). Stage 2: FC R beside the left features' selection and FC L,
  // which need the tracks. With parallel_images each stage runs as finer jobs on OpenCV's pool
  // (below).
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
  if (options_.parallel_images) {
    // DC first, then both detection chains, then LSS in parts (after DC) for the cores to
    // share; each part tracks a contiguous share of the points into its own record.
    std::vector<Job> jobs;
    jobs.push_back({[&] {
      pyramid = tracker_.build_pyramid(left, dc);
      dc.points = static_cast<std::int64_t>(previous_points_.size());
    }});
    jobs.push_back({left_detection});
    jobs.push_back({right_detection});
    std::array<std::vector<cv::Point2f>, kTrackParts> part_points;
    std::array<TrackResult, kTrackParts> part_tracks;
    std::array<trace::TaskRecord, kTrackParts> part_lss;
    const std::size_t n = previous_points_.size();
    for (std::size_t k = 0; k < kTrackParts; ++k) {
      const auto begin =
          previous_points_.begin() + static_cast<std::ptrdiff_t>(k * n / kTrackParts);
      const auto end =
          previous_points_.begin() + static_cast<std::ptrdiff_t>((k + 1) * n / kTrackParts);
      part_points[k].assign(begin, end);
      part_lss[k] = make_task(Task::LSS, Image::Left);
      jobs.push_back({[&, k] {
                        part_tracks[k] =
                            tracker_.track(previous_pyramid_, pyramid, part_points[k], part_lss[k]);
                      },
                      0});
    }
    clock.run_jobs(jobs);
    // One record and one result, as one call on all points makes them (levels, window and
    // per_level are the same in every part).
    lss = part_lss[0];
    for (std::size_t k = 1; k < kTrackParts; ++k) {
      lss.host_ns += part_lss[k].host_ns;
      lss.points += part_lss[k].points;
    }
    auto append = [](auto& to, const auto& from) { to.insert(to.end(), from.begin(), from.end()); };
    for (const TrackResult& part : part_tracks) {
      append(tracks.positions, part.positions);
      append(tracks.tracked, part.tracked);
      append(tracks.round_trip_px, part.round_trip_px);
      append(tracks.lk_residual, part.lk_residual);
      append(tracks.backward_from, part.backward_from);
    }
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
  if (options_.parallel_images) {
    // Both descriptions in two parts of levels each (describe_levels), merged per image.
    left_descriptors = FeatureExtractor::make_descriptors(left_keypoints);
    right_descriptors = FeatureExtractor::make_descriptors(right_keypoints);
    const std::array<std::vector<int>, 2> left_parts = describe_parts(left_corners.pyramid);
    const std::array<std::vector<int>, 2> right_parts = describe_parts(right_corners.pyramid);
    std::array<trace::TaskRecord, 2> left_fc{fc_left, fc_left}, right_fc{fc_right, fc_right};
    std::vector<Job> jobs;
    for (std::size_t p = 0; p < 2; ++p) {
      jobs.push_back({[&, p] {
        extractor_.describe_levels(right_corners.pyramid, right_smoothed, right_parts[p],
                                   right_keypoints, right_descriptors, right_fc[p]);
      }});
      jobs.push_back({[&, p] {
        extractor_.describe_levels(left_corners.pyramid, left_smoothed, left_parts[p],
                                   left_keypoints, left_descriptors, left_fc[p]);
      }});
    }
    clock.run_jobs(jobs);
    for (std::size_t p = 0; p < 2; ++p) {
      add_part(fc_left, left_fc[p]);
      add_part(fc_right, right_fc[p]);
    }
    extractor_.finish_description(left_keypoints, fc_left);
    extractor_.finish_description(right_keypoints, fc_right);
  } else {
    right_descriptors =
        extractor_.describe(right_corners.pyramid, right_smoothed, right_keypoints, fc_right);
    left_descriptors =
        extractor_.describe(left_corners.pyramid, left_smoothed, left_keypoints, fc_left);
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
  const std::int64_t now = trace::thread_cpu_ns();
  out.host_ns = clock.elapsed_ns(now);
  out.span_ns = clock.span_ns(now);
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
