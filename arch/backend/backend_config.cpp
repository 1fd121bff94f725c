#include "arch/backend/backend_config.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <limits>
#include <stdexcept>

#include "arch/common/yaml_fields.hpp"

namespace edx::arch {
namespace {

void require(bool ok, const char* field, const std::string& expected) {
  if (!ok) throw std::runtime_error(fmt::format("backend.{}: expected {}", field, expected));
}

}  // namespace

void BackendConfig::validate() const {
  require(clock_mhz > 0 && clock_mhz <= 1000, "clock_mhz", "a frequency in (0, 1000] MHz");
  require(gemm_block >= 1 && gemm_block <= 256, "gemm_block", "an integer in [1, 256]");
  require(decomp_block >= 1 && decomp_block <= 256, "decomp_block", "an integer in [1, 256]");
  require(inverse_lanes >= 1, "inverse_lanes", "an integer >= 1");
  require(transpose_words_per_cycle >= 1, "transpose_words_per_cycle", "an integer >= 1");
  require(trsv_lanes >= 1, "trsv_lanes", "an integer >= 1");
  require(divide_latency_cycles >= 1, "divide_latency_cycles", "an integer >= 1");
  require(sqrt_latency_cycles >= 1, "sqrt_latency_cycles", "an integer >= 1");
  require(scalar_bytes == 4 || scalar_bytes == 8, "scalar_bytes", "4 (float) or 8 (double)");
  require(spm_bytes >= 1, "spm_bytes", "an integer >= 1");
  require(pose_dim >= 1, "pose_dim", "an integer >= 1");
  require(landmark_dim >= 1, "landmark_dim", "an integer >= 1");
}

nlohmann::json BackendConfig::to_json() const {
  return {{"clock_mhz", clock_mhz},
          {"gemm_block", gemm_block},
          {"decomp_block", decomp_block},
          {"inverse_lanes", inverse_lanes},
          {"transpose_words_per_cycle", transpose_words_per_cycle},
          {"trsv_lanes", trsv_lanes},
          {"divide_latency_cycles", divide_latency_cycles},
          {"sqrt_latency_cycles", sqrt_latency_cycles},
          {"scalar_bytes", scalar_bytes},
          {"spm_bytes", spm_bytes},
          {"symmetric_optimization", symmetric_optimization},
          {"structured_inverse", structured_inverse},
          {"gemm_overlap_tiles", gemm_overlap_tiles},
          {"blocked_solvers", blocked_solvers},
          {"pose_dim", pose_dim},
          {"landmark_dim", landmark_dim}};
}

BackendConfig BackendConfig::from_yaml(const YAML::Node& node, const std::string& where,
                                       const std::string& prefix) {
  BackendConfig c;
  YamlFields f(node, where, prefix);
  f.read("clock_mhz", c.clock_mhz, 0.0);
  f.read("gemm_block", c.gemm_block, 1);
  f.read("decomp_block", c.decomp_block, 1);
  f.read("inverse_lanes", c.inverse_lanes, 1);
  f.read("transpose_words_per_cycle", c.transpose_words_per_cycle, 1);
  f.read("trsv_lanes", c.trsv_lanes, 1);
  f.read("divide_latency_cycles", c.divide_latency_cycles, 1);
  f.read("sqrt_latency_cycles", c.sqrt_latency_cycles, 1);
  f.read("scalar_bytes", c.scalar_bytes, 1);
  // Up to 2^31 - 1 bytes (2 GiB) through the integer reader.
  int spm_bytes =
      static_cast<int>(std::min<std::int64_t>(c.spm_bytes, std::numeric_limits<int>::max()));
  f.read("spm_bytes", spm_bytes, 1);
  c.spm_bytes = spm_bytes;
  f.read("symmetric_optimization", c.symmetric_optimization);
  f.read("structured_inverse", c.structured_inverse);
  f.read("gemm_overlap_tiles", c.gemm_overlap_tiles);
  f.read("blocked_solvers", c.blocked_solvers);
  f.read("pose_dim", c.pose_dim, 1);
  f.read("landmark_dim", c.landmark_dim, 1);
  f.finish();
  try {
    c.validate();
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();  // "backend.<key>: expected ..."
    const std::size_t dot = message.find('.');
    const std::size_t colon = message.find(':');
    f.fail(message.substr(dot + 1, colon - dot - 1), message.substr(colon + 2));
  }
  return c;
}

}  // namespace edx::arch
