#pragma once
// Fixtures shared by the backend accelerator tests: units small enough to check by hand, and a
// Kalman-gain kernel with the ops the VIO backend records (workloads/backend/vio/ekf_update.cpp).
#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "arch/backend/accelerators/fpga_matrix_units.hpp"
#include "arch/backend/backend_config.hpp"
#include "workloads/trace/records.hpp"

namespace edx::arch::testing {

/// The parameters of a platform's offload accelerator of kind fpga_matrix_units (throws
/// std::bad_cast for another kind).
inline const BackendConfig& fpga_config(const OffloadAccelerator& accelerator) {
  return dynamic_cast<const FpgaMatrixUnits&>(accelerator).config();
}

/// A `backend:` YAML map parsed as the platform parses it (kind fpga_matrix_units); errors name
/// `where`.
inline BackendConfig parse_backend(const YAML::Node& node, const std::string& where) {
  YamlFields fields(node, where, "backend");
  return fpga_config(*parse_component<OffloadAccelerator>(fields, kDefaultOffloadKind));
}

/// Replaces the parameters of instance `name` of `config` by `params` (YAML of its kind's keys,
/// e.g. "{block: 8}"; keys not given take their defaults).
inline void set_unit(BackendConfig& config, const std::string& name, const std::string& params) {
  for (MatrixUnitInstance& u : config.units) {
    if (u.name != name) continue;
    u = make_matrix_unit(u.name, u.unit->kind(), params, u.count);
    return;
  }
  throw std::logic_error("no backend unit " + name);
}

/// b = 4 (2b = 8 fill and drain cycles a tile), 2 x 2 decomposition lanes, 2 inverse, transpose
/// and substitution lanes, divider 10 and square root 5 cycles; `clock_mhz` as given;
/// `overlap_tiles` on the array, `blocked` decomposition and substitution when asked.
inline BackendConfig small_config(double clock_mhz = 150.0, bool overlap_tiles = false,
                                  bool blocked = false) {
  BackendConfig c;
  c.clock_mhz = clock_mhz;
  c.units = {
      make_matrix_unit("gemm", "systolic_array",
                       fmt::format("{{block: 4, overlap_tiles: {}}}", overlap_tiles)),
      make_matrix_unit(
          "decomposition", "decomposition",
          fmt::format(
              "{{block: 2, divide_latency_cycles: 10, sqrt_latency_cycles: 5, blocked: {}}}",
              blocked)),
      make_matrix_unit("inverse", "inverse", "{lanes: 2, divide_latency_cycles: 10}"),
      make_matrix_unit("transpose", "transpose", "{words_per_cycle: 2}"),
      make_matrix_unit(
          "substitution", "substitution",
          fmt::format("{{lanes: 2, divide_latency_cycles: 10, blocked: {}}}", blocked)),
  };
  return c;
}

/// The index of instance `name` in `config.units`.
inline std::size_t unit_index(const BackendConfig& config, const std::string& name) {
  for (std::size_t i = 0; i < config.units.size(); ++i) {
    if (config.units[i].name == name) return i;
  }
  throw std::logic_error("no backend unit " + name);
}

inline trace::KernelRecord kernel_of(std::string name, std::vector<trace::OpRecord> ops) {
  trace::KernelRecord k;
  k.kernel = std::move(name);
  k.accelerable = true;
  k.ops = std::move(ops);
  return k;
}

/// K = P Hᵀ S⁻¹ with H m x n: PHᵀ, S = H (PHᵀ) (+R), S = L Lᵀ, two triangular solves, Kᵀ -> K.
inline trace::KernelRecord kalman_gain(std::int64_t m, std::int64_t n) {
  namespace flags = trace::op_flags;
  using trace::Op;
  using trace::OpRecord;
  trace::KernelRecord k = kernel_of(
      "kalman_gain",
      {OpRecord{Op::Gemm, n, m, n, flags::kSymmetric | flags::kTransposeB, 0},
       OpRecord{Op::Gemm, m, m, n, flags::kSymmetric, 0},
       OpRecord{Op::Potrf, m, m, 0, flags::kSymmetric, 0},
       OpRecord{Op::Trsm, m, n, 0, flags::kLower, 0}, OpRecord{Op::Trsm, m, n, 0, flags::kUpper, 0},
       OpRecord{Op::Transpose, m, n, 0, 0, 0}});
  k.m = m;
  k.n = n;
  return k;
}

}  // namespace edx::arch::testing
