#include "workloads/trace/host_speed.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <nlohmann/json.hpp>
#include <stdexcept>

namespace edx::trace {

double median_of(std::vector<double> samples) {
  if (samples.empty()) throw std::invalid_argument("median of no samples");
  std::sort(samples.begin(), samples.end());
  const std::size_t n = samples.size();
  return n % 2 ? samples[n / 2] : 0.5 * (samples[n / 2 - 1] + samples[n / 2]);
}

std::string to_meta_value(const HostSpeed& speed) {
  return nlohmann::json{{"suite", speed.suite},
                        {"frontend_ms", speed.frontend_ms},
                        {"backend_ms", speed.backend_ms},
                        {"samples", speed.samples},
                        {"inputs", speed.inputs},
                        {"sample_frames", speed.sample_frames},
                        {"frontend_samples_ms", speed.frontend_samples_ms},
                        {"backend_samples_ms", speed.backend_samples_ms}}
      .dump();
}

HostSpeed host_speed_of(const TraceMeta& meta, const std::string& file) {
  const auto found = meta.find("host_speed");
  if (found == meta.end()) {
    throw std::runtime_error(fmt::format(
        "{}: meta lacks host_speed (the reference suite's times; re-trace with this edx)", file));
  }
  const auto fail = [&](const std::string& what) {
    return std::runtime_error(
        fmt::format("{}: meta host_speed: {}, got '{}'", file, what, found->second));
  };
  const auto json = nlohmann::json::parse(found->second, nullptr, false);
  if (!json.is_object()) throw fail("expected a JSON object");
  HostSpeed speed;
  const auto number = [&](const char* key) {
    const auto it = json.find(key);
    if (it == json.end() || !it->is_number()) throw fail(fmt::format("expected number {}", key));
    return it->get<double>();
  };
  const double suite = number("suite");
  speed.frontend_ms = number("frontend_ms");
  speed.backend_ms = number("backend_ms");
  const double samples = number("samples");
  if (suite < 1 || suite != static_cast<int>(suite)) throw fail("expected suite an integer >= 1");
  if (!(speed.frontend_ms > 0) || !(speed.backend_ms > 0)) {
    throw fail("expected frontend_ms and backend_ms > 0");
  }
  if (samples < 1 || samples != static_cast<int>(samples)) {
    throw fail("expected samples an integer >= 1");
  }
  speed.suite = static_cast<int>(suite);
  speed.samples = static_cast<int>(samples);
  const auto inputs = json.find("inputs");
  if (inputs != json.end() && inputs->is_string()) speed.inputs = inputs->get<std::string>();
  // The samples are optional; when present, three arrays of one length.
  if (json.contains("sample_frames")) {
    try {
      speed.sample_frames = json.at("sample_frames").get<std::vector<std::int64_t>>();
      speed.frontend_samples_ms = json.at("frontend_samples_ms").get<std::vector<double>>();
      speed.backend_samples_ms = json.at("backend_samples_ms").get<std::vector<double>>();
    } catch (const nlohmann::json::exception&) {
      throw fail("expected sample_frames, frontend_samples_ms, backend_samples_ms number arrays");
    }
    if (speed.frontend_samples_ms.size() != speed.sample_frames.size() ||
        speed.backend_samples_ms.size() != speed.sample_frames.size()) {
      throw fail("expected sample arrays of one length");
    }
    for (std::size_t i = 0; i < speed.sample_frames.size(); ++i) {
      if (speed.sample_frames[i] < 0 ||
          (i > 0 && speed.sample_frames[i] < speed.sample_frames[i - 1])) {
        throw fail("expected sample_frames non-negative and non-decreasing");
      }
      if (!(speed.frontend_samples_ms[i] > 0) || !(speed.backend_samples_ms[i] > 0)) {
        throw fail("expected every sample > 0 ms");
      }
    }
  }
  return speed;
}

}  // namespace edx::trace
