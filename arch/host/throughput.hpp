#pragma once
// What bounds each kind of host work, and a processor's rate on each bound, from its datasheet
// (docs/MODEL.md, "Host CPU: processors from their datasheets"; issue 41).
//
// A row of the op-count host model (host_costs.hpp) is one frontend task, backend kernel or a
// frame's rest. Each kind is bounded by one throughput class (bound_of): branchy scalar code,
// SIMD integer image work, dense floating point of one precision, or memory bandwidth. A
// processor P runs a row of that kind at its rate on the class, so the row's time on P follows
// from its time on a reference processor R (the calibrated one) by the two rates:
//
//   t_P(row) = t_R(row) × rate_R(class) / (rate_P(class) × efficiency_P)
//
// with the per-core rates of a datasheet (ProcessorDatasheet::rate):
//
//   scalar       f × issue_width × (out_of_order ? 1 : kInOrderScalarFactor)
//   simd_int     f × simd_int_pipes × min(simd_bits, kCodeSimdBits) / 16     (16-bit lanes)
//   fp32, fp64   f × flops_per_cycle × min(1, kCodeSimdBits / simd_bits)
//   memory       memory_gb_per_s
//
// f the sustained clock (GHz). The code's SIMD width caps the hardware's: the traced pipeline's
// vector code (OpenCV's universal intrinsics at their baseline width, Eigen without -mavx) is
// 128 bits wide on every processor, so a 256-bit AVX2 core runs it at half its datasheet peak.
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "arch/host/host_costs.hpp"
#include "common/config_fields.hpp"

namespace edx::arch {

/// The resource that bounds a kind of host work.
enum class ThroughputClass { kScalar, kSimdInteger, kFloat32, kFloat64, kMemory };
inline constexpr int kThroughputClasses = 5;
const char* to_string(ThroughputClass c);

/// The class bounding a row kind (a task "FD", a kernel "kalman_gain", "frontend_rest",
/// "backend_rest:<mode>"); a kind this edx does not know is scalar.
ThroughputClass bound_of(CostPart part, std::string_view kind);
/// Whether bound_of has an entry for the kind (every kind of the bundled cost table must).
bool has_declared_bound(CostPart part, std::string_view kind);
/// The bound's reason for a kind, one line (docs/MODEL.md lists the table from it).
std::string bound_reason(CostPart part, std::string_view kind);

/// Every declared bound as a Markdown table (kind, part, class, reason), frontend tasks first:
/// `edx host-costs bounds`, docs/MODEL.md "Each kind's bound".
std::string bounds_markdown();

/// Width of the traced pipeline's vector code, bits (see the header comment).
inline constexpr int kCodeSimdBits = 128;
/// Sustained scalar throughput of an in-order core relative to an out-of-order core of the same
/// issue width: (2.3 / 4.1 DMIPS/MHz) / (2 / 3 issue), the Cortex-A53 against the Cortex-A57
/// (ARM's published Dhrystone figures per clock; their decode widths), docs/MODEL.md.
inline constexpr double kInOrderScalarFactor = (2.3 / 4.1) / (2.0 / 3.0);

/// A processor core's throughput as its datasheet states it (per core; `cores` of them).
struct ProcessorDatasheet {
  double clock_ghz = 1.6;  ///< sustained clock of the cores running the pipeline
  int issue_width = 4;     ///< instructions decoded and issued a cycle
  bool out_of_order = true;
  int simd_bits = 256;               ///< vector register width the core executes at full rate
  int simd_int_pipes = 3;            ///< vector integer ALU pipes
  double fp32_flops_per_cycle = 32;  ///< peak, FMA = 2 flops, at simd_bits
  double fp64_flops_per_cycle = 16;
  double l1d_kib = 32, l2_kib = 256, llc_kib = 9216;  ///< per core / per core / shared
  double memory_gb_per_s = 38.4;                      ///< DRAM bandwidth, 10^9 B/s

  /// Work units a ns on one core of class `c` (see the header comment).
  double rate(ThroughputClass c) const;
  /// Every rate, by class name (results, docs).
  nlohmann::json rates_json() const;

  static const FieldList<ProcessorDatasheet>& fields();
};

}  // namespace edx::arch
