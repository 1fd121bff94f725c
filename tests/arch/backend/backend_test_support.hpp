#pragma once
// Fixtures shared by the backend accelerator tests: units small enough to check by hand, and a
// Kalman-gain kernel with the ops the VIO backend records (workloads/backend/vio/ekf_update.cpp).
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "arch/backend/backend_config.hpp"
#include "workloads/trace/records.hpp"

namespace edx::arch::testing {

/// b = 4 (2b = 8 fill and drain cycles a tile), 2 x 2 decomposition lanes, 2 inverse, transpose
/// and substitution lanes, divider 10 and square root 5 cycles; `clock_mhz` as given.
inline BackendConfig small_config(double clock_mhz = 150.0) {
  BackendConfig c;
  c.gemm_block = 4;
  c.decomp_block = 2;
  c.inverse_lanes = 2;
  c.transpose_words_per_cycle = 2;
  c.trsv_lanes = 2;
  c.divide_latency_cycles = 10;
  c.sqrt_latency_cycles = 5;
  c.clock_mhz = clock_mhz;
  return c;
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
