#include "arch/host/throughput.hpp"

#include <algorithm>
#include <map>
#include <stdexcept>

namespace edx::arch {
namespace {

struct Bound {
  ThroughputClass bound;
  const char* reason;
};

using C = ThroughputClass;

/// Frontend tasks (OpenCV 4 on the host, workloads/frontend).
const std::map<std::string, Bound, std::less<>>& task_bounds() {
  static const std::map<std::string, Bound, std::less<>> table = {
      {"FD", {C::kSimdInteger, "FAST's circle test over every pixel, 8-bit vector compares"}},
      {"IF", {C::kSimdInteger, "Gaussian over every pyramid pixel, 8/16-bit vector multiply-adds"}},
      {"DC", {C::kSimdInteger, "pyramid and Scharr derivatives, 16-bit vector arithmetic"}},
      {"DR",
       {C::kSimdInteger, "sums of absolute differences over the search windows, 8-bit vectors"}},
      {"LSS",
       {C::kSimdInteger, "LK window products in 16-bit fixed point (OpenCV's vectorized LK)"}},
      {"FC",
       {C::kScalar,
        "rBRIEF: 256 gathered pixel-pair comparisons and the orientation moment per "
        "keypoint (gathers do not vectorize)"}},
      {"MO", {C::kScalar, "Hamming distances (popcount) and the branchy best-match bookkeeping"}},
      {"frontend_rest", {C::kScalar, "keypoint bookkeeping between the tasks"}},
  };
  return table;
}

/// Backend kernels (Eigen 3, double precision, workloads/backends).
const std::map<std::string, Bound, std::less<>>& kernel_bounds() {
  const Bound dense{C::kFloat64, "dense double-precision matrix products and factorizations"};
  const Bound scalar{C::kScalar,
                     "per-feature or per-point loops of small fixed-size algebra, "
                     "branches and lookups"};
  const Bound copy{C::kMemory, "copies of covariance blocks (no arithmetic)"};
  static const std::map<std::string, Bound, std::less<>> table = {
      {"kalman_gain", dense},
      {"covariance_update", dense},
      {"covariance_propagation", dense},
      {"marginalization", dense},
      {"schur_complement", dense},
      {"normal_equations", dense},
      {"solve", dense},
      {"lm_iteration", dense},
      {"nullspace_projection", dense},
      {"compression", dense},
      {"gps_fusion", dense},
      {"cloning", copy},
      {"clone_marginalization", copy},
      {"projection", scalar},
      {"jacobians", scalar},
      {"linearization", scalar},
      {"triangulation", scalar},
      {"track_check", scalar},
      {"imu_propagation", scalar},
      {"initialization", scalar},
      {"tracking", scalar},
      {"keyframe_selection", scalar},
      {"preintegration", scalar},
      {"outlier_rejection", scalar},
      {"bow_query", scalar},
      {"matching", scalar},
      {"pnp", scalar},
      {"local_map", scalar},
      {"projection_matching", scalar},
      {"pose_refinement", scalar},
  };
  return table;
}

const Bound* find_bound(CostPart part, std::string_view kind) {
  if (part == CostPart::kBackendRest) {
    static const Bound rest{C::kScalar, "track bookkeeping per feature handed over"};
    return &rest;
  }
  const auto& table = part == CostPart::kBackendKernel ? kernel_bounds() : task_bounds();
  const auto it = table.find(kind);
  return it == table.end() ? nullptr : &it->second;
}

}  // namespace

std::string bounds_markdown() {
  std::string text = "| kind | part | bound | why |\n|---|---|---|---|\n";
  const auto rows = [&text](const auto& table, const char* part) {
    for (const auto& [kind, bound] : table) {
      text += "| `" + kind + "` | " + part + " | " + to_string(bound.bound) + " | " + bound.reason +
              " |\n";
    }
  };
  rows(task_bounds(), "frontend");
  rows(kernel_bounds(), "backend");
  Bound rest = *find_bound(CostPart::kBackendRest, "");
  text += std::string("| `backend_rest:<mode>` | backend | ") + to_string(rest.bound) + " | " +
          rest.reason + " |\n";
  return text;
}

const char* to_string(ThroughputClass c) {
  switch (c) {
    case C::kScalar:
      return "scalar";
    case C::kSimdInteger:
      return "simd_int";
    case C::kFloat32:
      return "fp32";
    case C::kFloat64:
      return "fp64";
    case C::kMemory:
      return "memory";
  }
  return "?";
}

ThroughputClass bound_of(CostPart part, std::string_view kind) {
  const Bound* b = find_bound(part, kind);
  return b ? b->bound : C::kScalar;
}

bool has_declared_bound(CostPart part, std::string_view kind) {
  return find_bound(part, kind) != nullptr;
}

std::string bound_reason(CostPart part, std::string_view kind) {
  const Bound* b = find_bound(part, kind);
  return b ? b->reason : "a kind this edx does not know: scalar";
}

double ProcessorDatasheet::rate(ThroughputClass c) const {
  const double code_share = std::min(1.0, double(kCodeSimdBits) / double(simd_bits));
  switch (c) {
    case C::kScalar:
      return clock_ghz * issue_width * (out_of_order ? 1.0 : kInOrderScalarFactor);
    case C::kSimdInteger:
      return clock_ghz * simd_int_pipes * std::min(simd_bits, kCodeSimdBits) / 16.0;
    case C::kFloat32:
      return clock_ghz * fp32_flops_per_cycle * code_share;
    case C::kFloat64:
      return clock_ghz * fp64_flops_per_cycle * code_share;
    case C::kMemory:
      return memory_gb_per_s;
  }
  throw std::logic_error("ProcessorDatasheet::rate: unknown class");
}

nlohmann::json ProcessorDatasheet::rates_json() const {
  nlohmann::json j;
  for (C c : {C::kScalar, C::kSimdInteger, C::kFloat32, C::kFloat64, C::kMemory}) {
    j[to_string(c)] = rate(c);
  }
  return j;
}

const FieldList<ProcessorDatasheet>& ProcessorDatasheet::fields() {
  using P = ProcessorDatasheet;
  static const FieldList<P> list = {
      field("clock_ghz", &P::clock_ghz, "GHz", "sustained clock of the cores running the pipeline",
            Bounds::above(0).below(10)),
      field("issue_width", &P::issue_width, "", "instructions decoded and issued a cycle a core",
            Bounds::at_least(1).at_most(16)),
      field("out_of_order", &P::out_of_order, "",
            "out-of-order core (false: in order, scalar rate x 0.84, docs/MODEL.md)"),
      field("simd_bits", &P::simd_bits, "bits", "vector width the core executes at full rate",
            Bounds::at_least(64).at_most(2048)),
      field("simd_int_pipes", &P::simd_int_pipes, "", "vector integer ALU pipes a core",
            Bounds::at_least(1).at_most(16)),
      field("fp32_flops_per_cycle", &P::fp32_flops_per_cycle, "flop/cycle",
            "peak single-precision flops a cycle a core (FMA = 2) at simd_bits",
            Bounds::above(0).at_most(1024)),
      field("fp64_flops_per_cycle", &P::fp64_flops_per_cycle, "flop/cycle",
            "peak double-precision flops a cycle a core (FMA = 2) at simd_bits",
            Bounds::above(0).at_most(1024)),
      field("l1d_kib", &P::l1d_kib, "KiB", "L1 data cache a core (recorded; not in the rates)",
            Bounds::above(0)),
      field("l2_kib", &P::l2_kib, "KiB", "L2 cache (recorded; not in the rates)", Bounds::above(0)),
      field("llc_kib", &P::llc_kib, "KiB", "last-level cache, shared (recorded; not in the rates)",
            Bounds::above(0)),
      field("memory_gb_per_s", &P::memory_gb_per_s, "GB/s", "DRAM bandwidth, 10^9 B/s",
            Bounds::above(0).at_most(10000)),
  };
  return list;
}

}  // namespace edx::arch
