#include "vio_run.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <Eigen/Dense>
#include <bit>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <map>
#include <random>
#include <stdexcept>
#include <string>

#include "workloads/backend/vio/chi_square.hpp"
#include "workloads/datasets/synthetic/generator.hpp"
#include "workloads/datasets/synthetic/renderer.hpp"
#include "workloads/frontend/stereo_frontend.hpp"

namespace edx::backend::vio::testing {
namespace {

std::span<const datasets::ImuSample> imu_between(const std::vector<datasets::ImuSample>& all,
                                                 std::int64_t after, std::int64_t upto) {
  const auto lo = std::upper_bound(all.begin(), all.end(), after,
                                   [](std::int64_t t, const auto& s) { return t < s.t_ns; });
  const auto hi = std::upper_bound(all.begin(), all.end(), upto,
                                   [](std::int64_t t, const auto& s) { return t < s.t_ns; });
  return {lo, hi};
}

std::span<const datasets::GpsFix> gps_between(const std::vector<datasets::GpsFix>& all,
                                              std::int64_t after, std::int64_t upto) {
  const auto lo = std::upper_bound(all.begin(), all.end(), after,
                                   [](std::int64_t t, const auto& s) { return t < s.t_ns; });
  const auto hi = std::upper_bound(all.begin(), all.end(), upto,
                                   [](std::int64_t t, const auto& s) { return t < s.t_ns; });
  return {lo, hi};
}

double yaw_of(const Eigen::Matrix3d& R) { return std::atan2(R(1, 0), R(0, 0)); }

using Observations = std::vector<std::pair<std::size_t, std::size_t>>;  // (frame, index)

/// Least-squares point of a track's left observations at the ground-truth left-camera poses
/// (linear triangulation, x P3 - P1 and y P3 - P2 rows, then Gauss-Newton on the pixels);
/// nothing when it is degenerate or falls behind a camera during the iterations.
std::optional<Eigen::Vector3d> triangulate_at_truth(
    const std::vector<frontend::FrontendFrame>& frames, const Observations& obs,
    const std::vector<std::optional<Eigen::Isometry3d>>& T_world_left,
    const datasets::CameraIntrinsics& K) {
  Eigen::Matrix4d A = Eigen::Matrix4d::Zero();
  for (const auto& [i, j] : obs) {
    const auto& f = frames[i].features[j];
    const Eigen::Matrix<double, 3, 4> P = T_world_left[i]->inverse().matrix().topRows<3>();
    const double x = (f.left.x - K.cx) / K.fx, y = (f.left.y - K.cy) / K.fy;
    const Eigen::RowVector4d r1 = x * P.row(2) - P.row(0), r2 = y * P.row(2) - P.row(1);
    A += r1.transpose() * r1 + r2.transpose() * r2;
  }
  const Eigen::Vector4d X = Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d>(A).eigenvectors().col(0);
  if (obs.size() < 2 || std::abs(X(3)) <= 1e-12) return std::nullopt;
  Eigen::Vector3d pw = X.head<3>() / X(3);
  for (int it = 0; it < 10; ++it) {
    Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
    Eigen::Vector3d b = Eigen::Vector3d::Zero();
    for (const auto& [i, j] : obs) {
      const auto& f = frames[i].features[j];
      const Eigen::Vector3d pc = T_world_left[i]->inverse() * pw;
      if (pc.z() < 0.1) return std::nullopt;
      const Eigen::Vector2d r(f.left.x - (K.fx * pc.x() / pc.z() + K.cx),
                              f.left.y - (K.fy * pc.y() / pc.z() + K.cy));
      Eigen::Matrix<double, 2, 3> J;
      J << K.fx / pc.z(), 0, -K.fx * pc.x() / (pc.z() * pc.z()), 0, K.fy / pc.z(),
          -K.fy * pc.y() / (pc.z() * pc.z());
      J = (J * T_world_left[i]->linear().transpose()).eval();
      H += J.transpose() * J;
      b += J.transpose() * r;
    }
    pw += H.ldlt().solve(b);
  }
  return pw;
}

/// Tracks by id, with their observations at frames whose ground truth is known.
std::map<int, Observations> tracks_of(const std::vector<frontend::FrontendFrame>& frames,
                                      const std::vector<std::optional<Eigen::Isometry3d>>& T) {
  std::map<int, Observations> tracks;
  for (std::size_t i = 0; i < frames.size(); ++i)
    for (std::size_t j = 0; j < frames[i].features.size(); ++j)
      if (T[i]) tracks[frames[i].features[j].id].push_back({i, j});
  return tracks;
}

/// Diagnostic ($EDX_VIO_IDEAL_FEATURES=sigma_px): every track of the frontend is replaced by the
/// exact projections of one static point (its least-squares triangulation from the left
/// observations at the ground-truth poses) plus white N(0, sigma^2) pixel noise, left and right.
/// Separates the filter's consistency from the frontend's (temporally correlated) track errors.
/// $EDX_VIO_IDEAL_PART=left keeps the frontend's disparities on exact left tracks;
/// =disparity keeps the frontend's left tracks with exact disparities (no noise added in either).
enum class IdealPart { kAll, kLeft, kDisparity };
void idealize_tracks(std::vector<frontend::FrontendFrame>& frames,
                     const std::vector<std::optional<Eigen::Isometry3d>>& T_world_left,
                     const datasets::CameraIntrinsics& K, double baseline_m, double sigma_px,
                     IdealPart part) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> noise(0.0, sigma_px);
  for (const auto& [id, obs] : tracks_of(frames, T_world_left)) {
    const std::optional<Eigen::Vector3d> pw = triangulate_at_truth(frames, obs, T_world_left, K);
    for (const auto& [i, j] : obs) {
      auto& f = frames[i].features[j];
      const Eigen::Vector3d pc =
          pw ? Eigen::Vector3d(T_world_left[i]->inverse() * *pw) : Eigen::Vector3d::Zero();
      if (!pw || pc.z() < 0.1) {
        f.id = -1;  // removed below (this observation only, when behind the camera)
        continue;
      }
      const cv::Point2f exact_left(static_cast<float>(K.fx * pc.x() / pc.z() + K.cx),
                                   static_cast<float>(K.fy * pc.y() / pc.z() + K.cy));
      const float exact_disparity = static_cast<float>(K.fx * baseline_m / pc.z());
      if (part == IdealPart::kLeft) {  // exact left track, the frontend's disparity
        const float disparity = f.disparity;
        f.left = exact_left;
        if (f.stereo) f.right = {f.left.x - disparity, f.left.y};
        continue;
      }
      if (part == IdealPart::kDisparity) {  // the frontend's left track, exact disparity
        if (f.stereo) {
          f.right = {f.left.x - exact_disparity, f.left.y};
          f.disparity = exact_disparity;
          f.depth_m = pc.z();
        }
        continue;
      }
      f.left = {exact_left.x + static_cast<float>(noise(rng)),
                exact_left.y + static_cast<float>(noise(rng))};
      if (f.stereo) {
        f.right = {static_cast<float>(K.fx * (pc.x() - baseline_m) / pc.z() + K.cx + noise(rng)),
                   f.left.y};
        f.disparity = f.left.x - f.right.x;
        f.stereo = f.disparity > 0;
        f.depth_m = f.stereo ? K.fx * baseline_m / f.disparity : 0.0;
      }
    }
  }
  for (auto& frame : frames)
    std::erase_if(frame.features, [](const frontend::Feature& f) { return f.id < 0; });
}

}  // namespace

double env_number(const char* name, double min) {
  const char* text = std::getenv(name);
  if (!text) throw std::invalid_argument(fmt::format("${}: not set", name));
  double value = 0;
  const char* end = text + std::strlen(text);
  const auto [stop, error] = std::from_chars(text, end, value);
  if (error != std::errc() || stop != end || !(value >= min)) {
    throw std::invalid_argument(
        fmt::format("${}: expected a number >= {}, got '{}'", name, min, text));
  }
  return value;
}

namespace {

/// Ends every track at its first observation (frame i, feature j) for which `ends` is true:
/// that and every later observation of the track are dropped. Returns the observations dropped.
long end_tracks_where(
    std::vector<frontend::FrontendFrame>& frames,
    const std::function<bool(std::size_t, std::size_t, const frontend::Feature&)>& ends) {
  std::map<std::int64_t, bool> ended;
  long removed = 0;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    for (std::size_t j = 0; j < frames[i].features.size(); ++j) {
      frontend::Feature& f = frames[i].features[j];
      if (ended[f.id] || ends(i, j, f)) {
        ended[f.id] = true;
        f.id = -1;
        ++removed;
      }
    }
  }
  for (auto& frame : frames)
    std::erase_if(frame.features, [](const frontend::Feature& f) { return f.id < 0; });
  return removed;
}

/// Diagnostic ($EDX_VIO_MAX_FLOW=px): every track ends at its first step whose image motion
/// |x_k - x_(k-1)| exceeds the bound (large steps are where translation-only LK errs most).
void cut_fast_tracks(std::vector<frontend::FrontendFrame>& frames, double max_flow_px) {
  std::map<std::int64_t, cv::Point2f> last;
  const long removed = end_tracks_where(frames, [&](std::size_t, std::size_t, const auto& f) {
    const auto it = last.find(f.id);
    const bool fast = it != last.end() &&
                      std::hypot(f.left.x - it->second.x, f.left.y - it->second.y) > max_flow_px;
    last[f.id] = f.left;
    return fast;
  });
  std::fprintf(stderr, "[flow] removed %ld observations (steps over %.1f px)\n", removed,
               max_flow_px);
}

/// Diagnostic ($EDX_VIO_MAX_TRACK_AGE=n): every track ends after its first n observations (the
/// control of the drift oracle below: shorter tracks without looking at the truth).
void cut_old_tracks(std::vector<frontend::FrontendFrame>& frames, long max_observations) {
  std::map<std::int64_t, long> seen;
  const long removed = end_tracks_where(frames, [&](std::size_t, std::size_t, const auto& f) {
    return ++seen[f.id] > max_observations;
  });
  std::fprintf(stderr, "[age] removed %ld observations (after %ld a track)\n", removed,
               max_observations);
}

/// Diagnostic ($EDX_VIO_DEPTH_TRUTH=1, synthetic datasets only): the frontend's disparities and
/// left tracks against the rendered truth. The generator's world is rebuilt from edx_gen.yaml
/// (scenario, seed) and each frame's left view rendered with depth at the true pose:
/// true disparity at a tracked pixel fx b / Z(u, v); a feature is "on an edge" when the depth
/// inside its DR window varies by more than 10 % (an occlusion boundary, or sky). Left-track
/// drift: the point seen at a track's first pixel (its rendered depth) reprojected into the
/// track's later frames; how well three frontend signals (descriptor Hamming distance to the
/// track's first, LK residual, forward-backward round trip) single out the drifted tracks.
/// Oracles (they change the run): $EDX_VIO_DEPTH_TRUTH_GATE=x drops stereo matches more than x
/// px off; $EDX_VIO_DEPTH_TRUTH_DRIFT_GATE=x ends tracks once they are x px off their point;
/// $EDX_VIO_DEPTH_TRUTH_EDGE_GATE=1 ends tracks once they touch an edge.
void check_against_depth_truth(std::vector<frontend::FrontendFrame>& frames,
                               const std::vector<std::optional<Eigen::Isometry3d>>& T_world_left,
                               const datasets::CameraIntrinsics& K, double baseline_m,
                               const std::filesystem::path& dataset_dir, int dr_window_px) {
  const std::filesystem::path gen_file = dataset_dir / "edx_gen.yaml";
  if (!std::filesystem::exists(gen_file)) {
    throw std::invalid_argument("$EDX_VIO_DEPTH_TRUTH: " + gen_file.string() +
                                ": not found (needs a dataset made by edx gen)");
  }
  const YAML::Node gen = YAML::LoadFile(gen_file.string());
  const synthetic::Scene scene =
      synthetic::build_scene(synthetic::parse_scenario(gen["scenario"].as<std::string>()),
                             gen["seed"].as<std::uint64_t>());
  synthetic::Renderer renderer(scene.world, 2);
  const synthetic::PinholeCamera camera{K.width, K.height, K.fx, K.fy, K.cx, K.cy};
  const int half = dr_window_px / 2;
  struct Sample {
    double disparity_error = 0;
    bool edge = false;
  };
  std::vector<std::vector<Sample>> samples(frames.size());
  std::vector<std::vector<Eigen::Vector3d>> points(frames.size());  // world point at the pixel
  for (std::size_t i = 0; i < frames.size(); ++i) {
    samples[i].resize(frames[i].features.size());
    points[i].assign(frames[i].features.size(), Eigen::Vector3d::Constant(std::nan("")));
    if (!T_world_left[i]) continue;
    std::vector<cv::Mat> radiance, depth;
    renderer.render({{camera, *T_world_left[i]}}, radiance, &depth);
    const cv::Mat& range = depth[0];
    auto z_at = [&](int u, int v) {  // depth along the optical axis at pixel (u, v)
      const double x = (u - K.cx) / K.fx, y = (v - K.cy) / K.fy;
      return static_cast<double>(range.at<float>(v, u)) / std::sqrt(x * x + y * y + 1.0);
    };
    for (std::size_t j = 0; j < frames[i].features.size(); ++j) {
      const auto& f = frames[i].features[j];
      const int u = cvRound(f.left.x), v = cvRound(f.left.y);
      if (u - half < 0 || v - half < 0 || u + half >= K.width || v + half >= K.height) {
        samples[i][j].edge = true;
        continue;
      }
      double lo = 1e30, hi = 0;
      for (int dv = -half; dv <= half; ++dv)
        for (int du = -half; du <= half; ++du) {
          const double z = z_at(u + du, v + dv);
          lo = std::min(lo, z);
          hi = std::max(hi, z);
        }
      const double z = z_at(u, v);
      samples[i][j].edge = !std::isfinite(hi) || hi > 1.1 * lo;
      if (f.stereo && std::isfinite(z))
        samples[i][j].disparity_error = f.disparity - K.fx * baseline_m / z;
      if (std::isfinite(z)) {
        const Eigen::Vector3d pc((f.left.x - K.cx) / K.fx * z, (f.left.y - K.cy) / K.fy * z, z);
        points[i][j] = *T_world_left[i] * pc;
      }
    }
  }
  // Disparity errors: on smooth surfaces and on edges, and their quantiles.
  std::vector<double> smooth, edge;
  double lag = 0, lag_norm = 0;
  std::vector<std::vector<double>> drift(11), drift_smooth(11);
  std::vector<double> step_x, step_y;                 // signed, k = 1, smooth
  std::vector<std::vector<double>> step_by_depth(4);  // |e|, k = 1, smooth, by depth of p0
  const double depth_edges[] = {5.0, 15.0, 40.0, 1e30};
  std::vector<std::vector<double>> step_by_flow(5);  // |e|, every step k >= 1, smooth, by flow
  std::vector<double> flow_sum(5, 0.0);
  const double flow_edges[] = {2.0, 5.0, 10.0, 20.0, 1e30};
  // The same steps by the patch's scale change |Z_(k-1) / Z_k - 1| (the window's warp).
  std::vector<std::vector<double>> step_by_scale(5);
  std::vector<double> scale_sum(5, 0.0), scale_flow_sum(5, 0.0);
  const double scale_edges[] = {0.005, 0.01, 0.02, 0.04, 1e30};
  const double gate = std::getenv("EDX_VIO_DEPTH_TRUTH_GATE")
                          ? std::atof(std::getenv("EDX_VIO_DEPTH_TRUTH_GATE"))
                          : 0.0;
  const double drift_gate = std::getenv("EDX_VIO_DEPTH_TRUTH_DRIFT_GATE")
                                ? std::atof(std::getenv("EDX_VIO_DEPTH_TRUTH_DRIFT_GATE"))
                                : 0.0;
  long dropped_stereo = 0, dropped_left = 0;
  const bool edge_gate = std::getenv("EDX_VIO_DEPTH_TRUTH_EDGE_GATE") != nullptr;
  // Frontend signals a drift check could use, against the track's drift (below).
  struct SignalSample {
    double drift_px;
    float hamming_to_first, lk_residual, round_trip_px;
    bool edge;
  };
  std::vector<SignalSample> signals;
  for (const auto& [id, obs] : tracks_of(frames, T_world_left)) {
    double last = std::nan("");
    const auto [i0, j0] = obs.front();
    const Eigen::Vector3d p0 = points[i0][j0];
    bool track_on_edge = false;
    for (std::size_t k = 0; k < obs.size(); ++k) {
      const auto [i, j] = obs[k];
      const auto& f = frames[i].features[j];
      const Sample& s = samples[i][j];
      track_on_edge = track_on_edge || s.edge;
      if (edge_gate && s.edge && k > 0) {  // this and every later observation
        for (std::size_t m = k; m < obs.size(); ++m)
          frames[obs[m].first].features[obs[m].second].id = -1;
        dropped_left += static_cast<long>(obs.size() - k);
        break;
      }
      if (f.stereo && f.disparity > 0 && s.disparity_error != 0) {
        (s.edge ? edge : smooth).push_back(s.disparity_error);
        if (!s.edge && !std::isnan(last)) {
          lag += s.disparity_error * last;
          lag_norm += s.disparity_error * s.disparity_error;
        }
        last = s.edge ? std::nan("") : s.disparity_error;
      } else {
        last = std::nan("");
      }
      if (k > 0 && std::isfinite(p0.x())) {
        const Eigen::Vector3d pc = T_world_left[i]->inverse() * p0;
        if (pc.z() > 0.1) {
          const double e = std::hypot(f.left.x - (K.fx * pc.x() / pc.z() + K.cx),
                                      f.left.y - (K.fy * pc.y() / pc.z() + K.cy));
          if (k <= 10) drift[k].push_back(e);
          if (f.lk_residual >= 0) {
            const auto& first = frames[i0].features[j0].descriptor;
            int hamming = 0;
            for (std::size_t b = 0; b < first.size(); ++b)
              hamming += std::popcount(static_cast<unsigned>(first[b] ^ f.descriptor[b]));
            signals.push_back(
                {e, static_cast<float>(hamming), f.lk_residual, f.round_trip_px, s.edge});
          }
          if (k <= 10 && !track_on_edge) drift_smooth[k].push_back(e);
          if (!track_on_edge && k <= 10) {
            // This step's error: e_k - e_{k-1} against the step's flow |x_k - x_{k-1}|.
            const auto& prev = frames[obs[k - 1].first].features[obs[k - 1].second];
            const Eigen::Vector3d pp = T_world_left[obs[k - 1].first]->inverse() * p0;
            const Eigen::Vector2d e_now(f.left.x - (K.fx * pc.x() / pc.z() + K.cx),
                                        f.left.y - (K.fy * pc.y() / pc.z() + K.cy));
            const Eigen::Vector2d e_prev(prev.left.x - (K.fx * pp.x() / pp.z() + K.cx),
                                         prev.left.y - (K.fy * pp.y() / pp.z() + K.cy));
            const double flow = std::hypot(f.left.x - prev.left.x, f.left.y - prev.left.y);
            std::size_t b = 0;
            while (flow > flow_edges[b]) ++b;
            step_by_flow[b].push_back((e_now - e_prev).norm());
            flow_sum[b] += flow;
            const double scale = std::abs(pp.z() / pc.z() - 1.0);
            std::size_t c = 0;
            while (scale > scale_edges[c]) ++c;
            step_by_scale[c].push_back((e_now - e_prev).norm());
            scale_sum[c] += scale;
            scale_flow_sum[c] += flow;
          }
          if (k == 1 && !track_on_edge) {
            step_x.push_back(f.left.x - (K.fx * pc.x() / pc.z() + K.cx));
            step_y.push_back(f.left.y - (K.fy * pc.y() / pc.z() + K.cy));
            const double z0 = (T_world_left[i0]->inverse() * p0).z();
            std::size_t b = 0;
            while (z0 > depth_edges[b]) ++b;
            step_by_depth[b].push_back(e);
          }
          if (drift_gate > 0 && e > drift_gate) {  // this and every later observation
            for (std::size_t m = k; m < obs.size(); ++m)
              frames[obs[m].first].features[obs[m].second].id = -1;
            dropped_left += static_cast<long>(obs.size() - k);
            break;
          }
        }
      }
      if (gate > 0 && f.stereo && std::abs(s.disparity_error) > gate) {
        auto& g = frames[i].features[j];
        g.stereo = false;
        g.disparity = 0;
        g.depth_m = 0;
        ++dropped_stereo;
      }
    }
  }
  auto summary = [](std::vector<double> e) {
    if (e.empty()) return std::string("none");
    double sum = 0, sq = 0;
    for (double x : e) sum += x, sq += x * x;
    std::vector<double> a(e.size());
    for (std::size_t k = 0; k < e.size(); ++k) a[k] = std::abs(e[k]);
    std::sort(a.begin(), a.end());
    const auto q = [&](double p) { return a[static_cast<std::size_t>(p * (a.size() - 1))]; };
    const double n = static_cast<double>(e.size());
    return fmt::format(
        "{} samples, mean {:+.3f} px, RMS {:.3f} px, |e| median {:.3f} / 90 % {:.3f} "
        "/ 99 % {:.3f} px, over 1 px {:.1f} %",
        e.size(), sum / n, std::sqrt(sq / n), q(0.5), q(0.9), q(0.99),
        100.0 *
            static_cast<double>(std::count_if(a.begin(), a.end(), [](double x) { return x > 1; })) /
            n);
  };
  std::fprintf(stderr, "[depth truth] disparity error, smooth: %s\n", summary(smooth).c_str());
  std::fprintf(stderr, "[depth truth] disparity error, on edges: %s\n", summary(edge).c_str());
  std::fprintf(stderr, "[depth truth] smooth lag-1 rho %.2f\n", lag_norm > 0 ? lag / lag_norm : 0);
  for (std::size_t k : {1, 2, 5, 10}) {
    std::fprintf(stderr, "[depth truth] left drift after %zu frames, all: %s\n", k,
                 summary(drift[k]).c_str());
    std::fprintf(stderr, "[depth truth] left drift after %zu frames, never on an edge: %s\n", k,
                 summary(drift_smooth[k]).c_str());
  }
  auto median = [](std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
    return v[v.size() / 2];
  };
  std::fprintf(stderr, "[depth truth] first step, smooth: signed median x %+.3f px, y %+.3f px\n",
               median(step_x), median(step_y));
  for (std::size_t b = 0; b < 4; ++b)
    std::fprintf(stderr, "[depth truth] first step, smooth, depth bin %zu (<= %.0f m): %s\n", b,
                 std::min(depth_edges[b], 999.0), summary(step_by_depth[b]).c_str());
  for (std::size_t b = 0; b < 5; ++b)
    std::fprintf(stderr,
                 "[depth truth] step error, smooth, flow bin %zu (<= %.0f px, mean %.1f px): %s\n",
                 b, std::min(flow_edges[b], 999.0),
                 flow_sum[b] / std::max<double>(1.0, static_cast<double>(step_by_flow[b].size())),
                 summary(step_by_flow[b]).c_str());
  for (std::size_t c = 0; c < 5; ++c) {
    const double n = std::max<double>(1.0, static_cast<double>(step_by_scale[c].size()));
    std::fprintf(stderr,
                 "[depth truth] step error, smooth, scale-change bin %zu (<= %.3f, mean %.4f, "
                 "mean motion %.1f px): %s\n",
                 c, std::min(scale_edges[c], 9.0), scale_sum[c] / n, scale_flow_sum[c] / n,
                 summary(step_by_scale[c]).c_str());
  }
  // Each signal thresholded at its 90 / 95 / 99 % quantile over the good observations (within
  // 0.5 px of the truth, never on an edge): the shares of the drifted (> 1 px), of the edge and
  // of all observations it flags. A usable drift check flags far more of the drifted than of all.
  const std::pair<const char*, float SignalSample::*> kSignals[] = {
      {"Hamming to the first descriptor", &SignalSample::hamming_to_first},
      {"LK residual", &SignalSample::lk_residual},
      {"round trip px", &SignalSample::round_trip_px}};
  auto percent = [](long part, long whole) {
    return whole > 0 ? 100.0 * static_cast<double>(part) / static_cast<double>(whole) : 0.0;
  };
  for (const auto& [name, field] : kSignals) {
    std::vector<float> good;
    for (const SignalSample& x : signals) {
      if (x.drift_px < 0.5 && !x.edge) good.push_back(x.*field);
    }
    if (good.empty()) continue;
    std::sort(good.begin(), good.end());
    for (double q : {0.9, 0.95, 0.99}) {
      const float threshold =
          good[static_cast<std::size_t>(q * static_cast<double>(good.size() - 1))];
      long drifted = 0, drifted_flagged = 0, edges = 0, edges_flagged = 0, flagged = 0;
      for (const SignalSample& x : signals) {
        const bool flag = x.*field > threshold;
        flagged += flag;
        if (x.drift_px > 1.0) ++drifted, drifted_flagged += flag;
        if (x.edge) ++edges, edges_flagged += flag;
      }
      std::fprintf(stderr,
                   "[depth truth] %s > %.3f (good q%.0f): flags %.1f %% of drifted > 1 px, "
                   "%.1f %% of edge, %.1f %% of all observations\n",
                   name, threshold, 100 * q, percent(drifted_flagged, drifted),
                   percent(edges_flagged, edges),
                   percent(flagged, static_cast<long>(signals.size())));
    }
  }
  std::fprintf(stderr, "[depth truth] dropped: %ld stereo observations, %ld left observations\n",
               dropped_stereo, dropped_left);
  for (auto& frame : frames)
    std::erase_if(frame.features, [](const frontend::Feature& f) { return f.id < 0; });
}

/// Diagnostic ($EDX_VIO_TRACK_STATS=1): the frontend's track errors as the MSCKF sees them.
/// Each track's first `length` left observations (the VIO's update_track_length) are
/// triangulated at the ground-truth poses; the residuals' RMS per track, binned, and the lag-1
/// correlation of consecutive residuals (x and y pooled) per bin and overall.
void print_track_stats(const std::vector<frontend::FrontendFrame>& frames,
                       const std::vector<std::optional<Eigen::Isometry3d>>& T_world_left,
                       const datasets::CameraIntrinsics& K, double baseline_m, std::size_t length) {
  // Disparity errors of the tracks whose triangulation is well conditioned (>= `length`
  // observations over >= 2 m of travel, depth <= 20 m): e = d - fx b / z, by the fractional
  // part of d (pixel locking of the SAD parabola shows as a mean that depends on it).
  std::vector<double> disparity_sum(5, 0.0), disparity_sq(5, 0.0);
  std::vector<long> disparity_n(5, 0);
  double disparity_lag = 0, disparity_lag_norm = 0;
  struct Bin {
    long tracks = 0;
    double sum_sq = 0, lag_xy = 0, lag_xx = 0, lag_yy = 0;
    long residuals = 0;
  };
  const std::vector<std::pair<double, std::string>> edges = {
      {0.3, "< 0.3 px"}, {0.6, "0.3-0.6 px"}, {1.0, "0.6-1 px"}, {2.0, "1-2 px"}, {1e9, "> 2 px"}};
  std::vector<Bin> bins(edges.size() + 1);  // last: all
  for (auto [id, obs] : tracks_of(frames, T_world_left)) {
    if (obs.size() < 3) continue;
    if (obs.size() > length) obs.resize(length);
    const std::optional<Eigen::Vector3d> pw = triangulate_at_truth(frames, obs, T_world_left, K);
    if (!pw) continue;
    std::vector<Eigen::Vector2d> r;
    double sq = 0;
    for (const auto& [i, j] : obs) {
      const auto& f = frames[i].features[j];
      const Eigen::Vector3d pc = T_world_left[i]->inverse() * *pw;
      if (pc.z() < 0.1) break;  // behind a camera at the final point: not a usable track
      r.emplace_back(f.left.x - (K.fx * pc.x() / pc.z() + K.cx),
                     f.left.y - (K.fy * pc.y() / pc.z() + K.cy));
      sq += r.back().squaredNorm() / 2;
    }
    if (r.size() < obs.size()) continue;
    const double travel = (T_world_left[obs.back().first]->translation() -
                           T_world_left[obs.front().first]->translation())
                              .norm();
    if (obs.size() >= length && travel >= 2.0) {
      double last = std::nan("");
      for (const auto& [i, j] : obs) {
        const auto& f = frames[i].features[j];
        const Eigen::Vector3d pc = T_world_left[i]->inverse() * *pw;
        if (!f.stereo || pc.z() > 20.0) {
          last = std::nan("");
          continue;
        }
        const double e = f.disparity - K.fx * baseline_m / pc.z();
        const auto bin = static_cast<std::size_t>(
            std::min(4.0, std::floor((f.disparity - std::floor(f.disparity)) * 5.0)));
        disparity_sum[bin] += e;
        disparity_sq[bin] += e * e;
        ++disparity_n[bin];
        if (!std::isnan(last)) {
          disparity_lag += e * last;
          disparity_lag_norm += e * e;
        }
        last = e;
      }
    }
    const double rms = std::sqrt(sq / static_cast<double>(r.size()));
    std::size_t b = 0;
    while (rms >= edges[b].first) ++b;
    for (Bin* bin : {&bins[b], &bins.back()}) {
      ++bin->tracks;
      bin->sum_sq += sq;
      bin->residuals += static_cast<long>(r.size());
      for (std::size_t k = 1; k < r.size(); ++k) {
        bin->lag_xy += r[k].dot(r[k - 1]);
        bin->lag_xx += r[k - 1].squaredNorm();
        bin->lag_yy += r[k].squaredNorm();
      }
    }
  }
  std::fprintf(stderr, "[tracks] first %zu observations at the true poses:", length);
  for (std::size_t b = 0; b < bins.size(); ++b) {
    const Bin& bin = bins[b];
    std::fprintf(stderr, " | %s: %ld tracks, RMS %.3f px, rho %.2f",
                 b < edges.size() ? edges[b].second.c_str() : "all", bin.tracks,
                 bin.residuals ? std::sqrt(bin.sum_sq / static_cast<double>(bin.residuals)) : 0.0,
                 bin.lag_xx > 0 ? bin.lag_xy / std::sqrt(bin.lag_xx * bin.lag_yy) : 0.0);
  }
  std::fprintf(stderr, "\n[tracks] disparity error d - fx b / z by frac(d):");
  double all_sum = 0, all_sq = 0;
  long all_n = 0;
  for (std::size_t b = 0; b < disparity_n.size(); ++b) {
    const double n = std::max(1.0, static_cast<double>(disparity_n[b]));
    std::fprintf(stderr, " | [%.1f, %.1f): %ld, mean %+.3f px, RMS %.3f px", 0.2 * b, 0.2 * (b + 1),
                 disparity_n[b], disparity_sum[b] / n, std::sqrt(disparity_sq[b] / n));
    all_sum += disparity_sum[b];
    all_sq += disparity_sq[b];
    all_n += disparity_n[b];
  }
  const double n = std::max(1.0, static_cast<double>(all_n));
  std::fprintf(stderr, " | all: %ld, mean %+.3f px, RMS %.3f px, lag-1 rho %.2f\n", all_n,
               all_sum / n, std::sqrt(all_sq / n),
               disparity_lag_norm > 0 ? disparity_lag / disparity_lag_norm : 0.0);
}

}  // namespace

std::pair<double, double> mean_sd(const std::vector<double>& values) {
  if (values.empty()) return {0, 0};
  double mean = 0;
  for (double v : values) mean += v;
  mean /= static_cast<double>(values.size());
  double var = 0;
  for (double v : values) var += (v - mean) * (v - mean);
  return {mean, values.size() > 1 ? std::sqrt(var / static_cast<double>(values.size() - 1)) : 0};
}

VioRun run_vio(const std::filesystem::path& path, const VioOptions& given, std::size_t frames,
               bool collect_kernels) {
  const VioOptions& options = given;
  const auto dataset = datasets::open_dataset(path, datasets::DatasetFormat::kEuroc);
  auto backend_base = make_vio_backend(*dataset, options);
  auto& backend = dynamic_cast<VioBackend&>(*backend_base);
  const auto& calibration = dataset->calibration();
  frontend::FrontendOptions frontend_options;
  // Diagnostics: small changes of the frontend ($EDX_VIO_FB_THRESHOLD, forward-backward
  // threshold in px, default 1; $EDX_VIO_FEATURES, left feature budget, default 1000) show how
  // much the runs move when the feature selection does.
  if (const char* env = std::getenv("EDX_VIO_FB_THRESHOLD")) {
    frontend_options.fb_threshold_px = std::atof(env);
  }
  if (const char* env = std::getenv("EDX_VIO_FEATURES")) {
    frontend_options.features_per_image = std::atoi(env);
  }
  if (const char* env = std::getenv("EDX_VIO_LK_ITERATIONS")) {
    frontend_options.lk_max_iterations = std::atoi(env);
  }
  if (const char* env = std::getenv("EDX_VIO_LK_EPSILON")) {
    frontend_options.lk_epsilon_px = std::atof(env);
  }
  if (const char* env = std::getenv("EDX_VIO_LK_WINDOW")) {
    frontend_options.lk_window_px = std::atoi(env);
  }
  if (const char* env = std::getenv("EDX_VIO_DR_WINDOW")) {
    frontend_options.dr_window_px = std::atoi(env);
  }
  frontend::StereoFrontend frontend(frontend_options,
                                    {calibration.rectified.fx, calibration.baseline_m});
  VioRun run;
  run.frames = frames == 0 ? dataset->frame_count() : std::min(frames, dataset->frame_count());
  eval::Trajectory gt, est, gt_g, est_g, est_w;  // _g, _w: frames after the GPS alignment
  gt.stamp_kind = est.stamp_kind = eval::StampKind::kSeconds;
  gt_g.stamp_kind = est_g.stamp_kind = est_w.stamp_kind = eval::StampKind::kSeconds;
  gt.source = "ground truth";
  est.source = "vio estimate";
  std::int64_t previous = std::numeric_limits<std::int64_t>::min();
  std::optional<Eigen::Isometry3d> T_filter_gt;  // 4-DoF gauge at initialization
  std::optional<Eigen::Vector3d> last_gt_position;
  double nees_sum = 0, gamma_sum = 0;
  long gamma_dof = 0;
  int nees_count = 0, nees_inside = 0;
  const double nees_lo = chi2_quantile(0.025, 6), nees_hi = chi2_quantile(0.975, 6);
  std::vector<frontend::FrontendFrame> ideal;
  const char* ideal_sigma = std::getenv("EDX_VIO_IDEAL_FEATURES");
  if (ideal_sigma || std::getenv("EDX_VIO_TRACK_STATS") || std::getenv("EDX_VIO_DEPTH_TRUTH") ||
      std::getenv("EDX_VIO_MAX_FLOW") || std::getenv("EDX_VIO_MAX_TRACK_AGE")) {
    // Settings parsed before the frames are run (a bad one costs nothing).
    const long max_track_age = std::getenv("EDX_VIO_MAX_TRACK_AGE")
                                   ? static_cast<long>(env_number("EDX_VIO_MAX_TRACK_AGE", 1))
                                   : 0;  // 0: no limit
    std::vector<std::optional<Eigen::Isometry3d>> T_world_left;
    for (std::size_t i = 0; i < run.frames; ++i) {
      const datasets::StereoFrame images = dataset->load_frame(i);
      ideal.push_back(frontend.process(images.left, images.right));
      const auto truth = datasets::interpolate_ground_truth(dataset->ground_truth(), images.t_ns);
      T_world_left.push_back(
          truth ? std::optional<Eigen::Isometry3d>(truth->T_world_body * calibration.T_body_left)
                : std::nullopt);
    }
    if (std::getenv("EDX_VIO_TRACK_STATS")) {
      print_track_stats(ideal, T_world_left, calibration.rectified, calibration.baseline_m,
                        static_cast<std::size_t>(options.update_track_length));
    }
    if (const char* flow = std::getenv("EDX_VIO_MAX_FLOW")) cut_fast_tracks(ideal, std::stod(flow));
    if (max_track_age > 0) cut_old_tracks(ideal, max_track_age);
    if (std::getenv("EDX_VIO_DEPTH_TRUTH")) {
      check_against_depth_truth(
          ideal, T_world_left, calibration.rectified, calibration.baseline_m,
          std::filesystem::exists(path / "edx_gen.yaml") ? path : path.parent_path(),
          frontend_options.dr_window_px);
    }
    if (ideal_sigma) {
      const char* part = std::getenv("EDX_VIO_IDEAL_PART");
      if (part && std::string(part) != "left" && std::string(part) != "disparity") {
        throw std::invalid_argument("$EDX_VIO_IDEAL_PART: expected 'left' or 'disparity', got '" +
                                    std::string(part) + "'");
      }
      const IdealPart ideal_part = !part                         ? IdealPart::kAll
                                   : std::string(part) == "left" ? IdealPart::kLeft
                                                                 : IdealPart::kDisparity;
      idealize_tracks(ideal, T_world_left, calibration.rectified, calibration.baseline_m,
                      std::stod(ideal_sigma), ideal_part);
    }
  }
  // Diagnosis ($EDX_VIO_FIRST_FRAME=k): the backend starts at frame k, as after a mode switch.
  const std::size_t first_frame =
      std::getenv("EDX_VIO_FIRST_FRAME") ? std::stoul(std::getenv("EDX_VIO_FIRST_FRAME")) : 0;
  for (std::size_t i = 0; i < run.frames; ++i) {
    const datasets::StereoFrame images = dataset->load_frame(i);
    if (i < first_frame) {
      if (ideal.empty()) frontend.process(images.left, images.right);
      previous = images.t_ns;
      continue;
    }
    const frontend::FrontendFrame features =
        ideal.empty() ? frontend.process(images.left, images.right) : ideal[i];
    BackendInput input;
    input.t_ns = images.t_ns;
    input.frontend = &features;
    input.left_image = &images.left;
    input.imu = imu_between(dataset->imu(), previous, images.t_ns);
    if (options.use_gps) input.gps = gps_between(dataset->gps(), previous, images.t_ns);
    previous = images.t_ns;
    const auto start = std::chrono::steady_clock::now();
    BackendOutput output = backend.process(input);
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    if (!output.T_world_body) continue;
    run.backend_ms.push_back(ms);
    for (const auto& k : output.kernels) run.kernel_ms_total[k.kernel] += k.host_ns * 1e-6;
    if (collect_kernels) run.kernels.push_back(output.kernels);
    if (backend.last_update().updated) ++run.visual_updates;
    gamma_sum += backend.last_update().gamma_sum;
    gamma_dof += backend.last_update().gamma_dof;
    run.gps_fused += backend.last_gps().fused;
    ++run.estimated;
    const auto truth = datasets::interpolate_ground_truth(dataset->ground_truth(), images.t_ns);
    if (!truth) continue;
    const double t_s = static_cast<double>(images.t_ns) * 1e-9;
    gt.poses.push_back(
        {t_s, static_cast<std::int64_t>(i), eval::Pose(truth->T_world_body.matrix()), 0});
    est.poses.push_back(
        {t_s, static_cast<std::int64_t>(i), eval::Pose(output.T_world_body->matrix()), 0});
    if (backend.gps_aligned()) {
      const VioState& s = backend.state();
      Eigen::Isometry3d T_g = Eigen::Isometry3d::Identity();
      T_g.linear() = Eigen::AngleAxisd(s.yaw_GV, Eigen::Vector3d::UnitZ()).toRotationMatrix();
      T_g.translation() = s.t_GV;
      gt_g.poses.push_back(gt.poses.back());
      est_w.poses.push_back(est.poses.back());
      est_g.poses.push_back({t_s, static_cast<std::int64_t>(i),
                             eval::Pose((T_g * *output.T_world_body).matrix()), 0});
    }
    if (last_gt_position)
      run.distance_m += (truth->T_world_body.translation() - *last_gt_position).norm();
    last_gt_position = truth->T_world_body.translation();
    // Filter-frame quantities (the filter frame is fixed at initialization).
    const VioState& state = backend.state();
    if (!T_filter_gt) {
      // The yaw about world z that leaves no z component in the rotation error
      // log(Rz(yaw) R_gt R_est^T) (yaw and position are the filter's gauge, fixed at start).
      double yaw = yaw_of(state.R_WI) - yaw_of(truth->T_world_body.linear());
      for (int it = 0; it < 5; ++it) {
        const Eigen::Matrix3d Rz =
            Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
        yaw -= so3_log(Rz * truth->T_world_body.linear() * state.R_WI.transpose()).z();
      }
      Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
      T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
      T.translation() = state.p_WI - T.linear() * truth->T_world_body.translation();
      T_filter_gt = T;
    }
    const Eigen::Isometry3d truth_out = *T_filter_gt * truth->T_world_body;  // in filter frame
    Eigen::Matrix<double, 6, 1> e;
    e.head<3>() = so3_log(truth_out.linear() * state.R_WI.transpose());
    e.tail<3>() = truth_out.translation() - state.p_WI;
    const double nees = e.dot(state.P.topLeftCorner<6, 6>().ldlt().solve(e));
    nees_sum += nees;
    run.nees.push_back(nees);
    ++nees_count;
    if (nees >= nees_lo && nees <= nees_hi) ++nees_inside;
    run.final_drift_m = e.tail<3>().norm();
    if (std::getenv("EDX_VIO_VERBOSE") && i % 20 == 0) {
      const Eigen::VectorXd sd = state.P.diagonal().head(15).cwiseSqrt();
      std::fprintf(stderr,
                   "frame %zu err th %.4f %.4f %.4f p %.3f %.3f %.3f | sd th %.4f %.4f %.4f p %.3f "
                   "%.3f %.3f v %.3f ba %.3f %.3f %.3f bg %.4f\n",
                   i, e(0), e(1), e(2), e(3), e(4), e(5), sd(0), sd(1), sd(2), sd(3), sd(4), sd(5),
                   sd(6), state.accel_bias.x(), state.accel_bias.y(), state.accel_bias.z(),
                   state.gyro_bias.norm());
      {
        // Camera orientation error (IMU tilt and extrinsics together), velocity and bias errors.
        const Eigen::Matrix3d R_wc_true = truth_out.linear() * calibration.T_body_left.linear();
        const Eigen::Vector3d e_cam = so3_log(R_wc_true * (state.R_WI * state.R_IC).transpose());
        const Eigen::Vector3d v_true =
            T_filter_gt->linear() * truth->velocity_m_s.value_or(Eigen::Vector3d::Zero());
        const Eigen::Vector3d ba_true = truth->accel_bias_m_s2.value_or(Eigen::Vector3d::Zero());
        std::fprintf(stderr,
                     "  cam th %.4f %.4f %.4f v err %.3f %.3f %.3f (sd z %.3f) ba err %.3f %.3f "
                     "%.3f corr(th_y,p_z) %.2f\n",
                     e_cam(0), e_cam(1), e_cam(2), (v_true - state.v_WI).x(),
                     (v_true - state.v_WI).y(), (v_true - state.v_WI).z(),
                     std::sqrt(state.P(kVel + 2, kVel + 2)), (ba_true - state.accel_bias).x(),
                     (ba_true - state.accel_bias).y(), (ba_true - state.accel_bias).z(),
                     state.P(1, kPos + 2) / std::sqrt(state.P(1, 1) * state.P(kPos + 2, kPos + 2)));
      }
      if (backend.gps_aligned()) {
        const Eigen::Isometry3d T_gv = T_filter_gt->inverse();
        std::fprintf(stderr,
                     "  gps yaw %.4f (true %.4f, sd %.4f) t %.3f %.3f %.3f (true %.3f %.3f %.3f, "
                     "sd z %.3f)\n",
                     state.yaw_GV, yaw_of(T_gv.linear()), std::sqrt(state.P(kGpsYaw, kGpsYaw)),
                     state.t_GV.x(), state.t_GV.y(), state.t_GV.z(), T_gv.translation().x(),
                     T_gv.translation().y(), T_gv.translation().z(),
                     std::sqrt(state.P(kGpsPos + 2, kGpsPos + 2)));
      }
    }
  }
  run.gps_aligned = backend.gps_aligned();
  if (gamma_dof > 0) run.gamma_per_dof = gamma_sum / static_cast<double>(gamma_dof);
  if (nees_count > 0) {
    run.mean_nees = nees_sum / nees_count;
    run.nees_in_bounds = static_cast<double>(nees_inside) / nees_count;
  }
  if (est.poses.size() >= 2) {
    eval::EvalOptions eval_options;
    eval_options.alignment = eval::AlignmentMethod::kPosYaw;
    eval_options.t_max_diff_s = 1e-3;
    run.accuracy = eval::evaluate(gt, est, eval_options);
    if (est_g.poses.size() >= 2) {
      run.global_accuracy = eval::evaluate(gt_g, est_g, eval_options);
      run.filter_accuracy_aligned_frames = eval::evaluate(gt_g, est_w, eval_options);
      eval::EvalOptions none = eval_options;
      none.alignment = eval::AlignmentMethod::kNone;
      run.global_unaligned = eval::evaluate(gt_g, est_g, none);
    }
    // Diagnosis ($EDX_VIO_AXES): the aligned error's RMS along track, across track and
    // vertically, and per 100 frames.
    if (std::getenv("EDX_VIO_AXES") && gt.poses.size() == est.poses.size()) {
      double along = 0, across = 0, up = 0, block = 0;
      std::string blocks;
      const std::size_t n = gt.poses.size();
      for (std::size_t k = 0; k < n; ++k) {
        const Eigen::Vector3d g = gt.poses[k].pose.translation();
        const Eigen::Vector3d e =
            run.accuracy->align.apply(Eigen::Vector3d(est.poses[k].pose.translation())) - g;
        const Eigen::Vector3d next = gt.poses[std::min(k + 1, n - 1)].pose.translation();
        const Eigen::Vector3d prev = gt.poses[k > 0 ? k - 1 : 0].pose.translation();
        Eigen::Vector3d dir = next - prev;
        dir.z() = 0;
        dir = dir.norm() > 1e-9 ? dir.normalized() : Eigen::Vector3d::UnitX();
        const Eigen::Vector3d side = Eigen::Vector3d::UnitZ().cross(dir);
        along += e.dot(dir) * e.dot(dir);
        across += e.dot(side) * e.dot(side);
        up += e.z() * e.z();
        block += e.squaredNorm();
        if ((k + 1) % 100 == 0 || k + 1 == n) {
          blocks += fmt::format(" {:.3f}", std::sqrt(block / static_cast<double>(k % 100 + 1)));
          block = 0;
        }
      }
      const double m = static_cast<double>(n);
      std::fprintf(stderr, "[axes] along %.3f across %.3f up %.3f | per 100 frames%s\n",
                   std::sqrt(along / m), std::sqrt(across / m), std::sqrt(up / m), blocks.c_str());
    }
  }
  return run;
}

}  // namespace edx::backend::vio::testing
