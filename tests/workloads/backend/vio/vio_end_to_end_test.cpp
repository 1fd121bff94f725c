// End-to-end runs of the VIO backend behind the real stereo frontend: small synthetic sequences
// (indoor drone, outdoor car with and without GPS) and the real EuRoC excerpt at rest.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <sstream>

#include "tests/support/temp_dir.hpp"
#include "tests/workloads/backend/vio/vio_run.hpp"
#include "workloads/backend/vio/chi_square.hpp"
#include "workloads/datasets/synthetic/generator.hpp"

namespace edx::backend::vio {
namespace {

namespace fs = std::filesystem;
using testing::run_vio;
using testing::VioRun;

fs::path generate(const fs::path& dir, synthetic::Scenario scenario, int frames,
                  std::optional<synthetic::Resolution> resolution, std::uint64_t seed = 1) {
  synthetic::GenerateOptions options;
  options.scenario = scenario;
  options.frames = frames;
  options.resolution = resolution;
  options.seed = seed;
  options.out = dir / "data";
  synthetic::generate_dataset(options);
  return options.out;
}

void print(const std::string& name, const VioRun& run) {
  const auto [mean, sd] = testing::mean_sd(run.backend_ms);
  double total = 0;
  for (const auto& [k, ms] : run.kernel_ms_total) total += ms;
  std::string kernels;
  for (const auto& [k, ms] : run.kernel_ms_total)
    kernels += fmt::format(" {}={:.1f}%", k, total > 0 ? 100 * ms / total : 0);
  fmt::print(
      "[vio] {}: frames {} estimated {} ATE {:.4f} m distance {:.1f} m final drift {:.3f} m "
      "({:.2f}%) NEES {:.2f} (in 95% bounds {:.0f}% of frames) updates {} gps fused {} "
      "gamma/dof {:.2f}\n"
      "[vio] {}: backend {:.2f} +- {:.2f} ms/frame; kernels:{}\n",
      name, run.frames, run.estimated, run.accuracy ? run.accuracy->ate_m.rmse : -1.0,
      run.distance_m, run.final_drift_m, 100 * run.final_drift_m / std::max(run.distance_m, 1e-9),
      run.mean_nees, 100 * run.nees_in_bounds, run.visual_updates, run.gps_fused, run.gamma_per_dof,
      name, mean, sd, kernels);
  if (run.global_accuracy) {
    fmt::print(
        "[vio] {}: after GPS alignment ({} frames): ATE GPS frame {:.4f} m (posyaw) {:.4f} m "
        "(unaligned), filter frame {:.4f} m (posyaw)\n",
        name, run.global_accuracy->pairs, run.global_accuracy->ate_m.rmse,
        run.global_unaligned->ate_m.rmse, run.filter_accuracy_aligned_frames->ate_m.rmse);
  }
  if (std::getenv("EDX_VIO_VERBOSE")) {
    std::string series;
    for (std::size_t i = 0; i < run.nees.size(); ++i) series += fmt::format(" {:.1f}", run.nees[i]);
    fmt::print("[vio] NEES per frame:{}\n", series);
  }
}

TEST(VioEndToEnd, IndoorDroneWithoutGps) {
  const edx::testing::TempDir dir;
  const fs::path data = generate(dir.path(), synthetic::Scenario::kIndoorUnknown, 160,
                                 synthetic::Resolution{376, 240});
  VioOptions options;
  options.use_gps = false;
  const VioRun run = run_vio(data, options, 0, /*collect_kernels=*/true);
  print("indoor 376x240 160 frames", run);
  ASSERT_TRUE(run.accuracy);
  // A pose on every frame from the one that completes the (moving) initialization on.
  EXPECT_EQ(run.estimated, static_cast<std::size_t>(160 - options.init_frames + 1));
  EXPECT_GT(run.visual_updates, 100);
  EXPECT_LT(run.accuracy->ate_m.rmse, 0.10);
  EXPECT_LT(run.final_drift_m, 0.01 * run.distance_m);
  // The kernels of the trace: every frame after the first propagates (the mean, then the
  // covariance with its ops), clones and (window full) marginalizes; kalman_gain is accelerable
  // with m = rows of H, n = state dim and six ops.
  std::set<std::string> names;
  int gains = 0;
  for (std::size_t f = 1; f < run.kernels.size(); ++f) {
    ASSERT_GE(run.kernels[f].size(), 3u);
    EXPECT_EQ(run.kernels[f][0].kernel, "imu_propagation");
    EXPECT_EQ(run.kernels[f][1].kernel, "covariance_propagation");
    EXPECT_EQ(run.kernels[f][1].m, run.kernels[f][0].m);
    EXPECT_FALSE(run.kernels[f][1].ops.empty());
    EXPECT_EQ(run.kernels[f][2].kernel, "cloning");
    for (const auto& k : run.kernels[f]) {
      names.insert(k.kernel);
      if (k.kernel != "kalman_gain") continue;
      ++gains;
      EXPECT_TRUE(k.accelerable);
      EXPECT_GT(k.m, 0);
      EXPECT_LE(k.m, k.n);  // groups of whole features of at most n rows (a feature has <= 27)
      EXPECT_LE(k.n, kCoreDim + kCloneDim * (options.max_clones + 1));  // before marginalizing
      EXPECT_EQ((k.n - kCoreDim) % kCloneDim, 0);
      ASSERT_EQ(k.ops.size(), 6u);
      EXPECT_EQ(k.ops[1].m, k.m);
      EXPECT_EQ(k.ops[1].k, k.n);
    }
  }
  EXPECT_GT(gains, 100);
  for (const char* name :
       {"imu_propagation", "covariance_propagation", "cloning", "triangulation", "jacobians",
        "nullspace_projection", "kalman_gain", "covariance_update", "clone_marginalization"}) {
    EXPECT_TRUE(names.contains(name)) << name;
  }
  EXPECT_FALSE(names.contains("compression"));  // off by default: Eq. 1 on the stacked H
  EXPECT_FALSE(names.contains("gps_fusion"));   // no GPS indoors
  EXPECT_FALSE(names.contains("track_check"));  // the first-window check is off by default
  // Consistency: the time-averaged 6-DoF NEES within the 95% interval of chi2(6).
  EXPECT_GT(run.mean_nees, chi2_quantile(0.025, 6));
  EXPECT_LT(run.mean_nees, chi2_quantile(0.975, 6));
}

// One outdoor sequence run twice: with the GPS fixes fused, and with them hidden.
TEST(VioEndToEnd, OutdoorCarWithAndWithoutGps) {
  const edx::testing::TempDir dir;
  const fs::path data = generate(dir.path(), synthetic::Scenario::kOutdoorUnknown, 160,
                                 synthetic::Resolution{640, 360});
  VioOptions options;
  options.use_gps = false;
  const VioRun vio = run_vio(data, options, 0);
  print("outdoor 640x360 160 frames, GPS ignored", vio);
  ASSERT_TRUE(vio.accuracy);
  EXPECT_FALSE(vio.gps_aligned);
  EXPECT_EQ(vio.gps_fused, 0);
  EXPECT_GT(vio.distance_m, 30.0);
  EXPECT_LT(vio.final_drift_m, 0.01 * vio.distance_m);
  EXPECT_LT(vio.accuracy->ate_m.rmse, 0.15);
  EXPECT_GT(vio.mean_nees, chi2_quantile(0.025, 6));
  EXPECT_LT(vio.mean_nees, chi2_quantile(0.975, 6));

  options.use_gps = true;
  const VioRun fused = run_vio(data, options, 0);
  print("outdoor 640x360 160 frames, GPS fused", fused);
  ASSERT_TRUE(fused.accuracy);
  EXPECT_TRUE(fused.gps_aligned);
  EXPECT_GT(fused.gps_fused, 40);
  // Issue 6's target, the paper's Fig. 3 figure for VIO + GPS (measured 0.079 m; 0.059 and
  // 0.082 m on seeds 2 and 3, docs/VIO.md).
  EXPECT_LT(fused.accuracy->ate_m.rmse, 0.10);
  EXPECT_LT(fused.final_drift_m, 0.01 * fused.distance_m);
  EXPECT_GT(fused.mean_nees, chi2_quantile(0.025, 6));
  EXPECT_LT(fused.mean_nees, chi2_quantile(0.975, 6));
}

TEST(VioEndToEnd, EurocAtRestStaysPut) {
  const fs::path data = fs::path(EDX_SHARED_DATA_DIR) / "euroc_v101_micro";
  VioOptions options;
  const VioRun run = run_vio(data, options, 0);
  print("euroc_v101_micro", run);
  ASSERT_GT(run.estimated, 50u);
  EXPECT_LT(run.final_drift_m, 0.05);
  // Consistent on real data: the gyro bias (0.077 rad/s about z in the dataset's ground-truth
  // state) is calibrated from the visual rotations at initialization, not left to a 0.005 rad/s
  // prior it is 15 sigma away from.
  EXPECT_GT(run.mean_nees, chi2_quantile(0.025, 6));
  EXPECT_LT(run.mean_nees, chi2_quantile(0.975, 6));
  // Deterministic: the same input gives the same estimate.
  const VioRun again = run_vio(data, options, 0);
  ASSERT_TRUE(run.accuracy && again.accuracy);
  EXPECT_EQ(again.estimated, run.estimated);
  EXPECT_EQ(again.final_drift_m, run.final_drift_m);
  EXPECT_EQ(again.accuracy->ate_m.rmse, run.accuracy->ate_m.rmse);
}

}  // namespace
}  // namespace edx::backend::vio

namespace edx::backend::vio {
namespace {

/// Full-size figures for the report (run by hand: --gtest_also_run_disabled_tests
/// --gtest_filter=*FullSize*). The datasets are generated once into $EDX_VIO_FULL_DIR
/// (default /tmp/edx_vio_full) and reused.
/// The generator seed of the hand-run figures: $EDX_VIO_SEED, default 1 (the tests' seed).
std::uint64_t seed_from_env() {
  const char* env = std::getenv("EDX_VIO_SEED");
  return env ? std::stoull(env) : 1;
}

fs::path full_size_dataset(const std::string& name, synthetic::Scenario scenario, int frames) {
  const char* env = std::getenv("EDX_VIO_FULL_DIR");
  const fs::path root = env ? fs::path(env) : fs::path("/tmp/edx_vio_full");
  const std::uint64_t seed = seed_from_env();
  const fs::path dir = root / (seed == 1 ? name : fmt::format("{}_seed{}", name, seed));
  if (!fs::exists(dir / "data" / "mav0")) {
    fs::create_directories(dir);
    generate(dir, scenario, frames, std::nullopt, seed);
  }
  return dir / "data";
}

/// Outdoor options with the diagnostic overrides of docs/VIO.md ($EDX_VIO_PIXEL_SIGMA, ...).
VioOptions diagnostic_options() {
  VioOptions options;
  if (const char* px = std::getenv("EDX_VIO_PIXEL_SIGMA")) options.pixel_sigma = std::stod(px);
  if (const char* rho = std::getenv("EDX_VIO_TRACK_CORRELATION"))
    options.track_error_correlation = std::stod(rho);
  if (const char* ba = std::getenv("EDX_VIO_BA_SIGMA"))
    options.init_accel_bias_sigma = std::stod(ba);
  if (std::getenv("EDX_VIO_EXT")) options.estimate_extrinsics = true;
  if (const char* rms = std::getenv("EDX_VIO_MAX_TRI_RMS"))
    options.max_triangulation_rms_px = std::stod(rms);
  if (const char* depth = std::getenv("EDX_VIO_MAX_DEPTH")) options.max_depth_m = std::stod(depth);
  if (std::getenv("EDX_VIO_GPS_HORIZONTAL")) options.gps_fuse_vertical = false;
  if (const char* extent = std::getenv("EDX_VIO_GPS_ALIGN_EXTENT"))
    options.gps_align_min_extent_m = std::stod(extent);
  // $EDX_VIO_WHITE=1: the white track noise model (before 2026-11-27); $EDX_VIO_RANDOM_WALK=
  // a,b,sd,sigma_d[,c] (px): the random-walk constants (c 0 when not given).
  // $EDX_VIO_FIRST_WINDOW_CHECK=px: the first-window check's bar (0: off, the default).
  if (std::getenv("EDX_VIO_FIRST_WINDOW_CHECK"))
    options.first_window_check_px = testing::env_number("EDX_VIO_FIRST_WINDOW_CHECK", 0);
  if (std::getenv("EDX_VIO_WHITE")) options.track_noise = VioOptions::TrackNoise::kWhite;
  if (const char* rw = std::getenv("EDX_VIO_RANDOM_WALK")) {
    RandomWalkTrackNoise& n = options.random_walk;
    n.step_scale_px = 0;
    if (std::sscanf(rw, "%lf,%lf,%lf,%lf,%lf", &n.step_sigma_px, &n.step_flow_fraction,
                    &n.detection_sigma_px, &n.disparity_sigma_px, &n.step_scale_px) < 4) {
      throw std::invalid_argument(
          std::string("$EDX_VIO_RANDOM_WALK: expected a,b,sd,sigma_d[,c], got '") + rw + "'");
    }
  }
  return options;
}

// The end-to-end sizes with other generator seeds ($EDX_VIO_SEED), to check that the figures
// are not particular to the tests' seed.
TEST(VioFullSize, DISABLED_TestSizesOtherSeed) {
  const std::uint64_t seed = seed_from_env();
  const edx::testing::TempDir dir;
  VioOptions options = diagnostic_options();
  options.use_gps = false;
  const bool fused_only = std::getenv("EDX_VIO_FUSED_ONLY") != nullptr;  // GPS diagnosis
  if (!fused_only) {
    const fs::path indoor = generate(dir.path() / "indoor", synthetic::Scenario::kIndoorUnknown,
                                     160, synthetic::Resolution{376, 240}, seed);
    print(fmt::format("seed {} indoor 376x240 160 frames", seed), run_vio(indoor, options, 0));
  }
  options = diagnostic_options();
  options.use_gps = false;
  const fs::path outdoor = generate(dir.path() / "outdoor", synthetic::Scenario::kOutdoorUnknown,
                                    160, synthetic::Resolution{640, 360}, seed);
  if (!fused_only) {
    print(fmt::format("seed {} outdoor 640x360 160 frames, GPS ignored", seed),
          run_vio(outdoor, options, 0));
  }
  options.use_gps = true;
  print(fmt::format("seed {} outdoor 640x360 160 frames, GPS fused", seed),
        run_vio(outdoor, options, 0));
}

TEST(VioFullSize, DISABLED_IndoorDrone1200Frames) {
  const fs::path data = full_size_dataset("indoor", synthetic::Scenario::kIndoorUnknown, 1200);
  VioOptions options;
  options.use_gps = false;
  print("FULL indoor 752x480 1200 frames", run_vio(data, options, 0));
}

TEST(VioFullSize, DISABLED_OutdoorCar) {
  const fs::path data = full_size_dataset("outdoor", synthetic::Scenario::kOutdoorUnknown, 400);
  VioOptions options = diagnostic_options();
  options.use_gps = false;
  print("FULL outdoor 1280x720 400 frames, GPS ignored", run_vio(data, options, 0));
  options.use_gps = true;
  print("FULL outdoor 1280x720 400 frames, GPS fused", run_vio(data, options, 0));
}

/// Seeds of the multi-seed check: $EDX_VIO_SEEDS ("11 12 13 14 15" when unset: none of them
/// was used to choose any option or constant).
std::vector<std::uint64_t> seeds_from_env() {
  const char* env = std::getenv("EDX_VIO_SEEDS");
  std::istringstream in(env ? env : "11 12 13 14 15");
  std::vector<std::uint64_t> seeds;
  for (std::uint64_t s; in >> s;) seeds.push_back(s);
  return seeds;
}

/// Min / median / max of a series, for the spread line.
std::string spread(std::vector<double> v) {
  if (v.empty()) return "-";
  std::sort(v.begin(), v.end());
  return fmt::format("{:.3f} / {:.3f} / {:.3f}", v.front(), v[v.size() / 2], v.back());
}

// The issue-16 targets at full size on seeds nobody tuned on (run by hand, ~3 min a seed):
// outdoor_unknown 600 frames at 752x480 (the reproduction: `edx gen --scenario
// outdoor_unknown --frames 600 --resolution 752x480 --seed S`, `edx trace --backend vio`), GPS
// fused (target ATE <= 0.10 m) and ignored, and indoor_unknown 600 frames at 752x480 without
// GPS (target ATE <= 0.27 m); NEES against its 95 % interval. Prints each run and the spread.
TEST(VioFullSize, DISABLED_SeedSpread) {
  const edx::testing::TempDir dir;
  // $EDX_VIO_SPREAD_DIR keeps the generated datasets there for later runs (diagnosis);
  // $EDX_VIO_FUSED_ONLY runs only the GPS-fused outdoor run of each seed.
  const char* keep = std::getenv("EDX_VIO_SPREAD_DIR");
  const fs::path root = keep ? fs::path(keep) : dir.path();
  const auto dataset = [&](const std::string& name, synthetic::Scenario scenario,
                           std::uint64_t seed) {
    const fs::path path = root / fmt::format("{}{}", name, seed);
    if (keep && fs::exists(path / "data" / "mav0")) return path / "data";
    return generate(path, scenario, 600, synthetic::Resolution{752, 480}, seed);
  };
  const bool fused_only = std::getenv("EDX_VIO_FUSED_ONLY") != nullptr;
  std::vector<double> fused, ignored, indoor, nees;
  for (const std::uint64_t seed : seeds_from_env()) {
    const fs::path outdoor = dataset("outdoor", synthetic::Scenario::kOutdoorUnknown, seed);
    VioOptions options = diagnostic_options();  // defaults unless a diagnosis overrides
    options.use_gps = true;
    const VioRun f = run_vio(outdoor, options, 0);
    print(fmt::format("seed {} outdoor 752x480 600 frames, GPS fused", seed), f);
    ASSERT_TRUE(f.accuracy.has_value());
    nees.push_back(f.mean_nees);
    fused.push_back(f.accuracy->ate_m.rmse);
    if (fused_only) continue;
    options.use_gps = false;
    const VioRun g = run_vio(outdoor, options, 0);
    print(fmt::format("seed {} outdoor 752x480 600 frames, GPS ignored", seed), g);
    const fs::path in = dataset("indoor", synthetic::Scenario::kIndoorUnknown, seed);
    const VioRun i = run_vio(in, options, 0);
    print(fmt::format("seed {} indoor 752x480 600 frames, no GPS", seed), i);
    for (const VioRun* r : {&g, &i}) {
      ASSERT_TRUE(r->accuracy.has_value());
      nees.push_back(r->mean_nees);
    }
    ignored.push_back(g.accuracy->ate_m.rmse);
    indoor.push_back(i.accuracy->ate_m.rmse);
  }
  std::printf(
      "[vio] spread over %zu seeds (min / median / max): ATE outdoor GPS fused %s m, GPS "
      "ignored %s m, indoor %s m; mean NEES %s (95%% interval [%.2f, %.2f])\n",
      fused.size(), spread(fused).c_str(), spread(ignored).c_str(), spread(indoor).c_str(),
      spread(nees).c_str(), chi2_quantile(0.025, 6), chi2_quantile(0.975, 6));
  for (double ate : fused) EXPECT_LE(ate, 0.10);
  for (double ate : indoor) EXPECT_LE(ate, 0.27);
}

}  // namespace
}  // namespace edx::backend::vio
