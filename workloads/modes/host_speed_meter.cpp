#include "workloads/modes/host_speed_meter.hpp"

#include <fmt/core.h>

#include <Eigen/Cholesky>
#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <algorithm>
#include <cstdint>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "workloads/frontend/stereo_frontend.hpp"
#include "workloads/frontend/task_timer.hpp"
#include "workloads/trace/host_clock.hpp"

namespace edx::modes {
namespace {

constexpr int kWidth = 1280, kHeight = 720;
constexpr int kMargin = 24;       ///< scene pixels beyond the views on every side
constexpr int kDisparityPx = 12;  ///< right view = left view shifted by this (fronto-parallel)
constexpr int kMotionX = 5, kMotionY = 3;  ///< second frame's shift against the first

/// Keeps the optimizer from dropping work whose result is not otherwise used.
volatile double g_sink = 0;

/// The scene the four views are cut from, in integer arithmetic only (bit-identical on every
/// machine): a bilinear value-noise background on a 32 px grid, 1800 filled rectangles and
/// circles of random grey, +-8 grey levels of pixel noise, then OpenCV's bit-exact 8-bit
/// Gaussian (5x5, sigma 1).
cv::Mat generate_scene() {
  cv::RNG rng(0x20261125);
  const int w = kWidth + 2 * kMargin + kDisparityPx + kMotionX;
  const int h = kHeight + 2 * kMargin + kMotionY;
  constexpr int kCell = 32;
  const int gw = w / kCell + 2, gh = h / kCell + 2;
  std::vector<int> grid(static_cast<std::size_t>(gw * gh));
  for (int& g : grid) g = rng.uniform(40, 216);
  cv::Mat scene(h, w, CV_8U);
  for (int y = 0; y < h; ++y) {
    const int gy = y / kCell, fy = y % kCell;
    for (int x = 0; x < w; ++x) {
      const int gx = x / kCell, fx = x % kCell;
      const int top = grid[gy * gw + gx] * (kCell - fx) + grid[gy * gw + gx + 1] * fx;
      const int bottom =
          grid[(gy + 1) * gw + gx] * (kCell - fx) + grid[(gy + 1) * gw + gx + 1] * fx;
      scene.at<std::uint8_t>(y, x) =
          static_cast<std::uint8_t>((top * (kCell - fy) + bottom * fy) / (kCell * kCell));
    }
  }
  for (int i = 0; i < 1800; ++i) {
    const cv::Point centre(rng.uniform(0, w), rng.uniform(0, h));
    const int size = rng.uniform(3, 28);
    const cv::Scalar grey(rng.uniform(0, 256));
    if (rng.uniform(0, 2) == 0) {
      cv::rectangle(scene, centre, centre + cv::Point(size, rng.uniform(3, 28)), grey, cv::FILLED);
    } else {
      cv::circle(scene, centre, size / 2, grey, cv::FILLED, cv::LINE_8);
    }
  }
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      auto& p = scene.at<std::uint8_t>(y, x);
      p = static_cast<std::uint8_t>(std::clamp(int(p) + rng.uniform(-8, 9), 0, 255));
    }
  }
  cv::GaussianBlur(scene, scene, cv::Size(5, 5), 1.0, 1.0, cv::BORDER_REFLECT_101);
  return scene;
}

/// A matrix of values in [-1, 1) from a 64-bit LCG (Knuth's MMIX constants).
Eigen::MatrixXd seeded_matrix(int rows, int cols, std::uint64_t seed) {
  Eigen::MatrixXd m(rows, cols);
  std::uint64_t state = seed;
  for (int j = 0; j < cols; ++j) {
    for (int i = 0; i < rows; ++i) {
      state = state * 6364136223846793005ULL + 1442695040888963407ULL;
      m(i, j) = static_cast<double>(state >> 11) * 0x1.0p-52 - 1.0;
    }
  }
  return m;
}

}  // namespace

HostSpeedMeter::HostSpeedMeter(HostSpeedMeterOptions options)
    : options_(options), images_(inputs()) {
  if (options_.initial_samples < 1 || options_.final_samples < 0 ||
      !(options_.work_per_sample >= 0)) {
    throw std::invalid_argument(
        "HostSpeedMeter: expected initial_samples >= 1, final_samples >= 0, work_per_sample >= 0");
  }
}

std::vector<cv::Mat> HostSpeedMeter::inputs() {
  const cv::Mat scene = generate_scene();
  const auto view = [&](int x, int y) {
    return scene(cv::Rect(kMargin + x, kMargin + y, kWidth, kHeight)).clone();
  };
  // Right view at x + d: a scene point at left column u is at right column u - d.
  return {view(0, 0), view(kDisparityPx, 0), view(kMotionX, kMotionY),
          view(kMotionX + kDisparityPx, kMotionY)};
}

std::string HostSpeedMeter::fingerprint(const std::vector<cv::Mat>& images) {
  std::uint64_t hash = 14695981039346656037ULL;
  for (const cv::Mat& image : images) {
    for (int y = 0; y < image.rows; ++y) {
      const std::uint8_t* row = image.ptr<std::uint8_t>(y);
      for (int x = 0; x < image.cols; ++x) hash = (hash ^ row[x]) * 1099511628211ULL;
    }
  }
  return fmt::format("{:016x}", hash);
}

double HostSpeedMeter::run_frontend_part() const {
  frontend::FrontendOptions options;
  options.parallel_images = options_.parallel_images;
  options.count_lk_iterations = false;
  const frontend::TracingThreads threads(options_.parallel_images);
  frontend::StereoFrontend frontend(options, {450.0, 0.11});
  // The frames' own work clock (FrontendFrame::host_ns), as a trace's frontend_host_ns.
  std::int64_t work_ns = 0;
  std::size_t features = 0;
  for (std::size_t pair = 0; pair < 2; ++pair) {
    const frontend::FrontendFrame frame =
        frontend.process(images_[2 * pair], images_[2 * pair + 1]);
    work_ns += frame.host_ns;
    features += frame.features.size();
  }
  g_sink = g_sink + static_cast<double>(features);
  return 1e-6 * static_cast<double>(work_ns);
}

double HostSpeedMeter::run_backend_part() const {
  // As the runners run the backend (modes/pipeline.hpp run_backend_timed): OpenCV's pool off.
  const frontend::TracingThreads single_threaded(false);
  const std::int64_t start = trace::thread_cpu_ns();
  double checksum = 0;
  // GEMM at a small and a mid size.
  for (const int n : {96, 384}) {
    const Eigen::MatrixXd a = seeded_matrix(n, n, 1 + n), b = seeded_matrix(n, n, 2 + n);
    const Eigen::MatrixXd c = a * b;
    checksum += c(n / 2, n / 3);
  }
  // Cholesky and a triangular solve with 64 right-hand sides on an SPD 256x256.
  {
    const Eigen::MatrixXd a = seeded_matrix(256, 256, 3);
    Eigen::MatrixXd spd = a * a.transpose();
    spd.diagonal().array() += 256.0;
    const Eigen::LLT<Eigen::MatrixXd> llt(spd);
    Eigen::MatrixXd rhs = seeded_matrix(256, 64, 4);
    llt.matrixL().solveInPlace(rhs);
    checksum += rhs(7, 3);
  }
  // Symmetric eigen-decomposition 160x160.
  {
    const Eigen::MatrixXd a = seeded_matrix(160, 160, 5);
    const Eigen::MatrixXd sym = a + a.transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(sym);
    checksum += eig.eigenvalues()(0);
  }
  // Householder QR of a tall 480x120.
  {
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(seeded_matrix(480, 120, 6));
    checksum += qr.matrixQR()(0, 0);
  }
  const std::int64_t end = trace::thread_cpu_ns();
  g_sink = g_sink + checksum;
  return 1e-6 * static_cast<double>(end - start);
}

void HostSpeedMeter::sample() {
  sample_frames_.push_back(frames_done_);
  frontend_ms_.push_back(run_frontend_part());
  backend_ms_.push_back(run_backend_part());
  last_sample_ms_ = frontend_ms_.back() + backend_ms_.back();
  work_since_sample_ns_ = 0;
}

void HostSpeedMeter::start() {
  run_frontend_part();
  run_backend_part();
  for (int i = 0; i < options_.initial_samples; ++i) sample();
}

void HostSpeedMeter::after_frame(std::int64_t frame_cpu_ns) {
  ++frames_done_;
  work_since_sample_ns_ += frame_cpu_ns;
  if (options_.work_per_sample > 0 && 1e-6 * static_cast<double>(work_since_sample_ns_) >=
                                          options_.work_per_sample * last_sample_ms_) {
    sample();
  }
}

void HostSpeedMeter::finish() {
  for (int i = 0; i < options_.final_samples; ++i) sample();
}

void HostSpeedMeter::finish_into(trace::TraceWriter& writer) {
  finish();
  writer.set_meta("host_speed", trace::to_meta_value(result()));
  writer.set_meta("frames", std::to_string(writer.frames_written()));  // the rows, checked on read
}

trace::HostSpeed HostSpeedMeter::result() const {
  trace::HostSpeed speed;
  speed.frontend_ms = trace::median_of(frontend_ms_);
  speed.backend_ms = trace::median_of(backend_ms_);
  speed.samples = static_cast<int>(frontend_ms_.size());
  speed.inputs = fingerprint(images_);
  speed.sample_frames = sample_frames_;
  speed.frontend_samples_ms = frontend_ms_;
  speed.backend_samples_ms = backend_ms_;
  return speed;
}

}  // namespace edx::modes
