// The matrix decomposition unit (paper Sec. VI-A, Table II "Matrix Decomposition"): Cholesky
// (potrf) and LDL^T (ldlt) on b_d x b_d multiply-accumulate lanes, with a pipelined divider and
// square root. docs/MODEL.md ("Backend accelerator") lists its formulas; L = b_d^2 lanes, c copies:
//
//   potrf  ⌈factorization_macs(m) / (L c)⌉ + m (t_sqrt + t_div)   a root and a reciprocal per
//          column stay on the critical path however many lanes share the products
//   ldlt   ⌈factorization_macs(m) / (L c)⌉ + m t_div              a reciprocal per column
//   blocked (Sec. VI-A, "the inherent blocking nature of matrix operations"): right-looking in
//          blocks of b = the array's tile (the unit serving syrk); per diagonal block j (size s,
//          `rest` rows below it): the block here (the unblocked formula at s), the panel on the
//          substitution unit (s + ⌈rest s (s+1)/2 / L_s⌉, its reciprocals known from the block;
//          L_s its MAC lanes) and the trailing update A_22 -= L_21 L_21^T as a syrk (rest x rest,
//          k = s) on the array. With m <= b it equals the unblocked formula.
//   resources  L MACs, one square root, one divider, operand registers, an address generator
#include <algorithm>

#include "arch/backend/matrix_unit.hpp"
#include "arch/backend/op_timing.hpp"
#include "arch/common/bounds.hpp"

namespace edx::arch {
namespace {

class Decomposition final : public MatrixUnit {
 public:
  struct Params {
    int block = 1;                   ///< b_d: b_d^2 MAC lanes (assumed; docs/MODEL.md)
    bool blocked = false;            ///< blocked factorization on the array (assumed)
    int divide_latency_cycles = 30;  ///< pipelined double divider (assumed)
    int sqrt_latency_cycles = 30;    ///< pipelined square root (assumed)
    static const FieldList<Params>& fields() {
      using C = Params;
      const Bounds positive = Bounds::at_least(1);
      static const FieldList<C> list = {
          field("block", &C::block, "",
                "b_d: b_d x b_d multiply-accumulate lanes (Edx-Car: 1, Table III's DSP budget)",
                positive.at_most(256)),
          field("blocked", &C::blocked, "",
                "blocked factorization: panels on the substitution unit, trailing updates on the "
                "array serving syrk"),
          field("divide_latency_cycles", &C::divide_latency_cycles, "cycles",
                "latency of its pipelined divider (a reciprocal per column)",
                bounds::latency_cycles()),
          field("sqrt_latency_cycles", &C::sqrt_latency_cycles, "cycles",
                "latency of its pipelined square root (Cholesky: a root per column)",
                bounds::latency_cycles()),
      };
      return list;
    }
    void validate() const { check_fields(*this, "decomposition", fields()); }
  };
  explicit Decomposition(const Params& params) : params_(params) {}

  std::string_view kind() const override { return "decomposition"; }
  nlohmann::json params_json() const override { return params_to_json(params_); }
  bool serves(trace::Op op) const override {
    return op == trace::Op::Potrf || op == trace::Op::Ldlt;
  }
  std::string building_block() const override { return "Cholesky / LDLᵀ decomposition"; }
  double mac_lanes() const override { return double(params_.block) * params_.block; }

  std::int64_t cycles(const trace::OpRecord& op, int copies,
                      const BackendConfig& backend) const override {
    const std::int64_t m = op.m;
    if (m == 0) return 0;
    const std::int64_t per_column =
        op.op == trace::Op::Potrf ? params_.sqrt_latency_cycles + params_.divide_latency_cycles
                                  : params_.divide_latency_cycles;
    if (params_.blocked) return blocked_cycles(m, per_column, copies, backend);
    return unblocked_cycles(m, per_column, copies);
  }

  cost::Resources resources(cost::Arithmetic a) const override {
    return factorization_datapath(mac_lanes(), a);
  }

 private:
  std::int64_t unblocked_cycles(std::int64_t m, std::int64_t per_column, int copies) const {
    const std::int64_t lanes = std::int64_t(params_.block) * params_.block * std::max(1, copies);
    return ceil_div(factorization_macs(m), lanes) + m * per_column;
  }

  std::int64_t blocked_cycles(std::int64_t m, std::int64_t per_column, int copies,
                              const BackendConfig& backend) const {
    const MatrixUnitInstance& array = serving_unit(trace::Op::Syrk, backend);
    const MatrixUnitInstance& panel = serving_unit(trace::Op::Trsm, backend);
    const std::int64_t b = array.unit->tile();
    const std::int64_t panel_lanes =
        static_cast<std::int64_t>(panel.unit->mac_lanes()) * panel.count;
    std::int64_t cycles = 0;
    for (std::int64_t done = 0; done < m; done += b) {
      const std::int64_t s = std::min(b, m - done);
      const std::int64_t rest = m - done - s;
      cycles += unblocked_cycles(s, per_column, copies);  // the diagonal block
      if (rest == 0) break;
      cycles += s + ceil_div(rest * s * (s + 1) / 2, panel_lanes);
      cycles += array.unit->cycles({trace::Op::Syrk, rest, rest, s, 0, 0}, array.count, backend);
    }
    return cycles;
  }

  Params params_;
};

}  // namespace

EDX_REGISTER_COMPONENT(MatrixUnit, Decomposition, "decomposition",
                       "Cholesky / LDLᵀ on b_d² MAC lanes: potrf, ldlt (Table II)");

}  // namespace edx::arch
