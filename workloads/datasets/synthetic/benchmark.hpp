#pragma once
// Render-speed benchmark of the synthetic world (for `./edx bench render`): renders a stereo
// sequence along a planned trajectory and reports frames per second. A stereo frame is two
// rendered images (left and right) including the sensor model (gain, blur, noise), excluding
// PNG encoding.
#include <cstdint>
#include <optional>
#include <string>

#include "workloads/datasets/synthetic/rig.hpp"

namespace edx::synthetic {

struct RenderBenchmarkOptions {
  bool outdoor = false;                  ///< street world (car rig) instead of the warehouse
  std::optional<Resolution> resolution;  ///< default: the rig's native resolution
  std::optional<RigKind> rig;            ///< default: euroc indoors, car outdoors
  int frames = 60;                       ///< stereo frames timed (after 2 warm-up frames)
  int threads = 2;
  std::uint64_t seed = 1;
  bool sensor_effects = true;
};

struct RenderBenchmarkResult {
  std::string world;
  int width = 0, height = 0;
  int threads = 0;
  int frames = 0;
  double setup_seconds = 0;        ///< world and trajectory construction
  double seconds = 0;              ///< rendering the timed frames
  double stereo_frames_per_s = 0;  ///< pairs of images per second
  double images_per_s = 0;
  double ms_per_stereo_frame = 0;
  double rays_per_s = 0;
  double box_tests_per_ray = 0;  ///< slab tests per pixel (acceleration structure quality)
  double tile_entries_per_frame = 0;
};

RenderBenchmarkResult benchmark_render(const RenderBenchmarkOptions& options);

}  // namespace edx::synthetic
