#include "workloads/datasets/synthetic/benchmark.hpp"

#include <chrono>
#include <stdexcept>

#include "workloads/datasets/synthetic/generator.hpp"
#include "workloads/datasets/synthetic/random.hpp"
#include "workloads/datasets/synthetic/scenes.hpp"
#include "workloads/datasets/synthetic/stereo_camera.hpp"
#include "workloads/datasets/synthetic/trajectory.hpp"

namespace edx::synthetic {

RenderBenchmarkResult benchmark_render(const RenderBenchmarkOptions& options) {
  if (options.frames < 1) throw std::runtime_error("benchmark: frames must be positive");
  using Clock = std::chrono::steady_clock;
  const auto t_setup = Clock::now();
  const RigKind kind = options.rig.value_or(options.outdoor ? RigKind::kCar : RigKind::kEuroc);
  const StereoRig rig = make_rig(kind, options.resolution.value_or(native_resolution(kind)));
  const Scene scene = build_scene(
      options.outdoor ? Scenario::kOutdoorUnknown : Scenario::kIndoorUnknown, options.seed);
  constexpr int kWarmup = 2;
  const double duration = (options.frames + kWarmup) / 20.0;
  const PlannedTrajectory planned =
      plan_trajectory(scene, duration, derive_seed(options.seed, "run", 0),
                      {rig.T_body_left.translation(), rig.T_body_right().translation()});
  ImageSensorOptions sensor;
  sensor.enabled = options.sensor_effects;
  StereoCamera camera(scene.world, rig, sensor, options.seed, options.threads);

  RenderBenchmarkResult result;
  result.world = options.outdoor ? "street" : "warehouse";
  result.width = rig.width;
  result.height = rig.height;
  result.threads = options.threads;
  result.frames = options.frames;
  result.setup_seconds = std::chrono::duration<double>(Clock::now() - t_setup).count();

  for (int k = 0; k < kWarmup; ++k) camera.capture(planned.trajectory.at(k / 20.0).T_world_body());
  std::int64_t rays = 0, tests = 0, entries = 0;
  const auto t0 = Clock::now();
  for (int k = 0; k < options.frames; ++k) {
    camera.capture(planned.trajectory.at((k + kWarmup) / 20.0).T_world_body());
    const RenderStats& stats = camera.renderer().last_stats();
    rays += stats.rays;
    tests += stats.box_tests;
    entries += stats.tile_entries;
  }
  result.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  result.stereo_frames_per_s = options.frames / result.seconds;
  result.images_per_s = 2.0 * result.stereo_frames_per_s;
  result.ms_per_stereo_frame = 1e3 * result.seconds / options.frames;
  result.rays_per_s = static_cast<double>(rays) / result.seconds;
  result.box_tests_per_ray = rays > 0 ? static_cast<double>(tests) / static_cast<double>(rays) : 0;
  result.tile_entries_per_frame = static_cast<double>(entries) / options.frames;
  return result;
}

}  // namespace edx::synthetic
