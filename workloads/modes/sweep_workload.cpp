// Workload points of sweeps: parsing, and tracing one as `edx trace --mix` does.
#include "workloads/modes/sweep_workload.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <stdexcept>

#include "workloads/datasets/dataset.hpp"
#include "workloads/frontend/task_timer.hpp"
#include "workloads/modes/mix_runner.hpp"
#include "workloads/trace/precision_field.hpp"

namespace edx::modes {
namespace {

/// An exclusive advisory lock on a file, held for the object's life (flock(2): threads and
/// processes that open the file each get their own lock).
class FileLock {
 public:
  explicit FileLock(const std::filesystem::path& path)
      : fd_(::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644)) {
    if (fd_ < 0 || ::flock(fd_, LOCK_EX) != 0) {
      if (fd_ >= 0) ::close(fd_);
      throw std::runtime_error(fmt::format("{}: cannot lock", path.string()));
    }
  }
  ~FileLock() {
    ::flock(fd_, LOCK_UN);
    ::close(fd_);
  }
  FileLock(const FileLock&) = delete;
  FileLock& operator=(const FileLock&) = delete;

 private:
  int fd_;
};

}  // namespace

const FieldList<SweepWorkload>& SweepWorkload::fields() {
  using C = SweepWorkload;
  static const FieldList<C> list = {
      choice_field("mix", &C::mix, "", mix_names(), "the mixed sequence (docs/MODES.md)"),
      field("frames", &C::frames, "", "frames of the whole mix",
            Bounds::at_least(8).at_most(1000000)),
      accessor_field<C>(
          "resolution", FieldKind::kText,
          [](const C& c) -> FieldValue {
            return fmt::format("{}x{}", c.resolution.width, c.resolution.height);
          },
          [](C& c, const FieldValue& v) {
            const std::string& text = std::get<std::string>(v);
            try {
              const cv::Size size = datasets::parse_resolution(text);
              c.resolution = {size.width, size.height};
            } catch (const std::runtime_error&) {
              throw InputError::expected("resolution", "WIDTHxHEIGHT in pixels (e.g. 640x480)",
                                         text);
            }
          },
          "px", "the rendered resolution, WxH"),
      field("features", &C::features, "",
            "keypoint budget per image (FrontendOptions::features_per_image)",
            Bounds::at_least(1).at_most(100000)),
      field("seed", &C::seed, "", "seed of the synthetic worlds",
            Bounds::at_least(0).at_most(9007199254740992.0)),
      field("msckf_window", &C::msckf_window, "", "VIO clones (VioOptions::max_clones)",
            Bounds::at_least(2).at_most(1000)),
      field("slam_window", &C::slam_window, "", "SLAM keyframes (SlamOptions::window_size)",
            Bounds::at_least(2).at_most(1000)),
      trace::precision_field(&C::precision,
                             "arithmetic of the offloadable backend kernels (fp64|fp32)"),
      optional_field("map_frames", &C::map_frames, "",
                     "frames of the mix's mapping run (default: the mix's own)",
                     Bounds::at_least(2).at_most(1000000), Unset{"default", nullptr}),
  };
  return list;
}

nlohmann::json SweepWorkload::to_json() const { return fields_to_json(*this, fields()); }

SweepWorkload SweepWorkload::from_json(const nlohmann::json& parameters) {
  if (!parameters.is_object()) throw InputError({}, "", "expected a map of workload parameters");
  YamlFields fields(yaml_of_json(parameters), "", "");
  const std::vector<std::string> keys = field_keys(SweepWorkload::fields());
  fields.refuse_unknown(keys, fmt::format("expected one of: {}", fmt::join(keys, ", ")));
  SweepWorkload w;
  parse_fields(fields, w, SweepWorkload::fields());
  return w;
}

void trace_sweep_workload(const SweepWorkload& workload, const std::filesystem::path& out,
                          const std::filesystem::path& data_dir) {
  MixRunOptions options;
  options.plan = make_mix(workload.mix, workload.frames, workload.resolution, workload.seed,
                          workload.map_frames);
  options.data_dir = data_dir;
  options.out = out;
  options.overwrite = true;
  options.save_maps = false;
  options.frontend.features_per_image = workload.features;
  options.vio.max_clones = workload.msckf_window;
  options.slam.window_size = workload.slam_window;
  options.precision = workload.precision;
  // A sweep runs one trace per worker: one render thread each.
  options.generator_threads = 1;
  std::filesystem::create_directories(data_dir);
  // OpenCV on one thread for the whole of it, the worlds' generation included: the setting is
  // the process's, and other workers trace at the same time (frontend::TracingThreads).
  const frontend::TracingThreads single_threaded(false);
  {
    // Worlds and vocabulary are shared by every workload with the same resolution and seed
    // (worlds also by frames): made once, by whoever holds their lock first; others wait, then
    // reuse them. Workloads of other resolutions or seeds generate at the same time.
    const FileLock lock(data_dir / fmt::format(".lock-{}x{}-s{}", workload.resolution.width,
                                               workload.resolution.height, workload.seed));
    prepare_mix_data(options);
  }
  run_mix(options);
}

}  // namespace edx::modes
