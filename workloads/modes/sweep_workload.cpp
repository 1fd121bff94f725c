// Workload points of sweeps: parsing, and tracing one as `edx trace --mix` does.
#include "workloads/modes/sweep_workload.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <limits>
#include <stdexcept>

#include "workloads/datasets/dataset.hpp"
#include "workloads/modes/mix_runner.hpp"

namespace edx::modes {
namespace {

/// An integer in [lo, hi] given as a JSON number or as text.
std::int64_t integer(const nlohmann::json& value, const std::string& key, std::int64_t lo,
                     std::int64_t hi) {
  std::int64_t v = 0;
  bool ok = false;
  if (value.is_number_integer()) {
    v = value.get<std::int64_t>();
    ok = true;
  } else if (value.is_number_float()) {
    const double d = value.get<double>();
    ok = d == static_cast<double>(static_cast<std::int64_t>(d));
    v = static_cast<std::int64_t>(d);
  } else if (value.is_string()) {
    const std::string& s = value.get_ref<const std::string&>();
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    ok = ec == std::errc() && end == s.data() + s.size();
  }
  if (!ok || v < lo || v > hi) {
    throw std::runtime_error(
        fmt::format("{}: expected an integer from {} to {}, got {}", key, lo, hi, value.dump()));
  }
  return v;
}

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

nlohmann::json SweepWorkload::to_json() const {
  return {{"mix", mix},
          {"frames", frames},
          {"resolution", fmt::format("{}x{}", resolution.width, resolution.height)},
          {"features", features},
          {"seed", seed},
          {"msckf_window", msckf_window},
          {"slam_window", slam_window},
          {"map_frames", map_frames ? nlohmann::json(*map_frames) : nlohmann::json(nullptr)}};
}

SweepWorkload SweepWorkload::from_json(const nlohmann::json& parameters) {
  if (!parameters.is_object()) throw std::runtime_error("workload: expected a map");
  SweepWorkload w;
  for (const auto& [key, value] : parameters.items()) {
    if (key == "mix") {
      if (!value.is_string()) throw std::runtime_error("mix: expected a mix name");
      w.mix = value.get<std::string>();
      const std::vector<std::string> names = mix_names();
      if (std::find(names.begin(), names.end(), w.mix) == names.end()) {
        throw std::runtime_error(fmt::format("mix: unknown mix '{}' (expected one of: {})", w.mix,
                                             fmt::join(names, ", ")));
      }
    } else if (key == "frames") {
      w.frames = static_cast<int>(integer(value, key, 8, 1000000));
    } else if (key == "resolution") {
      if (!value.is_string()) throw std::runtime_error("resolution: expected WxH");
      try {
        const cv::Size size = datasets::parse_resolution(value.get<std::string>());
        w.resolution = {size.width, size.height};
      } catch (const std::exception& e) {
        throw std::runtime_error(fmt::format("resolution: {}", e.what()));
      }
    } else if (key == "features") {
      w.features = static_cast<int>(integer(value, key, 1, 100000));
    } else if (key == "seed") {
      w.seed = static_cast<std::uint64_t>(integer(value, key, 0, std::int64_t{1} << 53));
    } else if (key == "msckf_window") {
      w.msckf_window = static_cast<int>(integer(value, key, 2, 1000));
    } else if (key == "slam_window") {
      w.slam_window = static_cast<int>(integer(value, key, 2, 1000));
    } else if (key == "map_frames") {
      if (value.is_null() || value == "~" || value == "default") {
        w.map_frames.reset();
      } else {
        w.map_frames = static_cast<int>(integer(value, key, 2, 1000000));
      }
    } else {
      throw std::runtime_error(fmt::format(
          "{}: unknown workload parameter (expected one of: mix, frames, resolution, features, "
          "seed, msckf_window, slam_window, map_frames)",
          key));
    }
  }
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
  // A sweep runs one trace per worker: one render thread each.
  options.generator_threads = 1;
  std::filesystem::create_directories(data_dir);
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
