#pragma once
// The workload of a sweep point (`workload:` in a sweep spec, docs/SWEEPS.md "Workload
// parameters"): the parameters of one traced run of a mix through the mode switch. A sweep
// traces each distinct workload point once (content-addressed by to_json() and the source
// revision) and simulates its platform points on that trace.
//
//   mix: paper          the mixed sequence (mix.hpp): paper, outdoor, indoor_unknown, indoor_known
//   frames: 400         frames of the whole mix (>= 8)
//   resolution: 640x480 the rendered resolution, WxH
//   features: 1000      keypoint budget per image (FrontendOptions::features_per_image)
//   seed: 1             seed of the synthetic worlds
//   msckf_window: 30    VIO clones (VioOptions::max_clones)
//   slam_window: 10     SLAM keyframes (SlamOptions::window_size)
//   precision: fp64     arithmetic of the offloadable backend kernels (fp64|fp32)
//   map_frames: ~       frames of the mix's mapping run: the size of the map registration uses
//                       (~ or default: the mix's own, a quarter of the paper mix)
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "common/config_fields.hpp"
#include "workloads/datasets/synthetic/rig.hpp"
#include "workloads/trace/records.hpp"

namespace edx::modes {

struct SweepWorkload {
  std::string mix = "paper";
  int frames = 400;
  synthetic::Resolution resolution{640, 480};
  int features = 1000;
  std::uint64_t seed = 1;
  int msckf_window = 30;
  int slam_window = 10;
  trace::Precision precision = trace::Precision::kFp64;
  std::optional<int> map_frames;  ///< the mix's default when empty

  /// Every parameter once: key, accepted values and a line of doc; to_json() and from_json()
  /// come from it.
  static const FieldList<SweepWorkload>& fields();
  /// Every parameter, typed (numbers as numbers, resolution as "WxH", map_frames null when
  /// unset): the content of the workload's hash.
  nlohmann::json to_json() const;
  /// From a map of parameter names to numbers or text ("500" and 500 alike); missing keys keep
  /// their defaults. Throws InputError "key: message" for an unknown key or a bad value.
  static SweepWorkload from_json(const nlohmann::json& parameters);
};

/// Traces the workload into `out` (all or nothing, as `edx trace --mix`), generating the worlds
/// and the vocabulary under `data_dir` (shared between workloads and between processes: the
/// generation holds an exclusive lock on data_dir/.lock). Throws std::runtime_error.
void trace_sweep_workload(const SweepWorkload& workload, const std::filesystem::path& out,
                          const std::filesystem::path& data_dir);

}  // namespace edx::modes
