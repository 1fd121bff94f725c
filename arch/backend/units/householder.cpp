// A Householder QR unit (beyond the paper's Table II: the MSCKF's null-space projection factors
// each feature's H_f, a 2k x 3 block, by Householder QR; workloads/backend/vio/msckf_updater.cpp).
// L MAC lanes with a pipelined square root and divider. docs/MODEL.md ("Backend accelerator"):
//
//   qr m x n  Σ_{j < min(m, n)} [ ⌈r_j / (L c)⌉ + t_sqrt + t_div + ⌈2 r_j (n - j - 1) / (L c)⌉ ]
//             r_j = m - j: column j's norm (r_j MACs), then its reflector's root and reciprocal
//             on the critical path, then the reflector applied to the columns right of it
//             (w = vᵀA, A -= τ v wᵀ: 2 r_j MACs a column); c copies share the lanes
//   resources L MACs, one square root, one divider, operand registers, an address generator
//
// The reflectors applied to other matrices (Qᵀ H_x) are products (gemm on the array); this unit
// only factors. Not in Edx-Car or Edx-Drone: a platform adds it under backend.units.
#include <algorithm>

#include "arch/backend/matrix_unit.hpp"
#include "arch/backend/op_timing.hpp"
#include "arch/common/bounds.hpp"

namespace edx::arch {
namespace {

class Householder final : public MatrixUnit {
 public:
  struct Params {
    int lanes = 4;                   ///< L (assumed)
    int divide_latency_cycles = 30;  ///< pipelined double divider (assumed, as decomposition)
    int sqrt_latency_cycles = 30;    ///< pipelined square root (assumed, as decomposition)
    static const FieldList<Params>& fields() {
      using C = Params;
      const Bounds positive = Bounds::at_least(1);
      static const FieldList<C> list = {
          field("lanes", &C::lanes, "", "L: multiply-accumulate lanes", positive.at_most(4096)),
          field("divide_latency_cycles", &C::divide_latency_cycles, "cycles",
                "latency of its pipelined divider (a reciprocal per reflector)",
                bounds::latency_cycles()),
          field("sqrt_latency_cycles", &C::sqrt_latency_cycles, "cycles",
                "latency of its pipelined square root (a norm per reflector)",
                bounds::latency_cycles()),
      };
      return list;
    }
    void validate() const { check_fields(*this, "householder", fields()); }
  };
  explicit Householder(const Params& params) : params_(params) {}

  std::string_view kind() const override { return "householder"; }
  nlohmann::json params_json() const override { return params_to_json(params_); }
  bool serves(trace::Op op) const override { return op == trace::Op::Qr; }
  std::string building_block() const override { return "Householder QR factorization"; }
  double mac_lanes() const override { return params_.lanes; }

  std::int64_t cycles(const trace::OpRecord& op, int copies, const BackendConfig&) const override {
    const std::int64_t lanes = std::int64_t(params_.lanes) * std::max(1, copies);
    const std::int64_t per_reflector = params_.sqrt_latency_cycles + params_.divide_latency_cycles;
    std::int64_t cycles = 0;
    for (std::int64_t j = 0; j < std::min(op.m, op.n); ++j) {
      const std::int64_t rows = op.m - j, right = op.n - j - 1;
      cycles += ceil_div(rows, lanes) + per_reflector + ceil_div(2 * rows * right, lanes);
    }
    return cycles;
  }

  cost::Resources resources(cost::Arithmetic a) const override {
    return factorization_datapath(mac_lanes(), a);
  }

 private:
  Params params_;
};

}  // namespace

EDX_REGISTER_COMPONENT(MatrixUnit, Householder, "householder",
                       "Householder QR on L MAC lanes with a square root and divider: qr");

}  // namespace edx::arch
