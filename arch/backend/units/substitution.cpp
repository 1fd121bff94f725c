// The forward/back substitution unit (paper Sec. VI-A, Table II "Fwd./Bwd. Substitution"): trsm
// and trsv, column-oriented, on L multiply-accumulate lanes with a pipelined divider.
// docs/MODEL.md ("Backend accelerator") lists its formulas; an m x m triangle against rhs
// right-hand sides (trsv: rhs = 1), c copies:
//
//   unblocked  t_div + (m - 1) + m + ⌈rhs m (m+1)/2 / (L c)⌉: the reciprocals of the diagonal
//              (pipelined), one broadcast cycle per column, the products on the lanes
//   blocked    in blocks of b rows (b = the array's tile, the unit serving gemm; s_i = min(b,
//              m - i b)): the reciprocals once (t_div + m - 1), then per block row the update
//              B_i -= L_i,<i X_<i as a gemm (s_i x rhs, k = i b) on the array (none for the first)
//              and the s_i x s_i solve here (s_i + ⌈rhs s_i (s_i+1)/2 / (L c)⌉). With m <= b it
//              equals the unblocked formula.
//   resources  L MACs, one divider, operand registers, an address generator
#include <algorithm>

#include "arch/backend/matrix_unit.hpp"
#include "arch/backend/op_timing.hpp"
#include "arch/common/bounds.hpp"

namespace edx::arch {
namespace {

class Substitution final : public MatrixUnit {
 public:
  struct Params {
    int lanes = 1;                   ///< L (assumed; Table III's DSP budget, docs/MODEL.md)
    bool blocked = false;            ///< block rows with their updates on the array (assumed)
    int divide_latency_cycles = 30;  ///< pipelined double divider (assumed)
    static const FieldList<Params>& fields() {
      using C = Params;
      const Bounds positive = Bounds::at_least(1);
      static const FieldList<C> list = {
          field("lanes", &C::lanes, "", "multiply-accumulate lanes (Edx-Car: 1)", positive),
          field("blocked", &C::blocked, "",
                "blocked substitution: the block rows' updates on the array serving gemm"),
          field("divide_latency_cycles", &C::divide_latency_cycles, "cycles",
                "latency of its pipelined divider (the diagonal's reciprocals)",
                bounds::latency_cycles()),
      };
      return list;
    }
    void validate() const { check_fields(*this, "substitution", fields()); }
  };
  explicit Substitution(const Params& params) : params_(params) {}

  std::string_view kind() const override { return "substitution"; }
  nlohmann::json params_json() const override { return params_to_json(params_); }
  bool serves(trace::Op op) const override {
    return op == trace::Op::Trsm || op == trace::Op::Trsv;
  }
  std::string building_block() const override { return "forward / back substitution"; }
  double mac_lanes() const override { return params_.lanes; }

  std::int64_t cycles(const trace::OpRecord& op, int copies,
                      const BackendConfig& backend) const override {
    const std::int64_t m = op.m;
    const std::int64_t rhs = op.op == trace::Op::Trsv ? 1 : op.n;
    if (m == 0 || rhs == 0) return 0;
    const std::int64_t lanes = std::int64_t(params_.lanes) * std::max(1, copies);
    const std::int64_t t_div = params_.divide_latency_cycles;
    if (!params_.blocked) return t_div + (m - 1) + m + ceil_div(rhs * m * (m + 1) / 2, lanes);
    const MatrixUnitInstance& array = serving_unit(trace::Op::Gemm, backend);
    const std::int64_t b = array.unit->tile();
    std::int64_t cycles = t_div + (m - 1);  // all reciprocals, pipelined
    for (std::int64_t done = 0; done < m; done += b) {
      const std::int64_t s = std::min(b, m - done);
      if (done > 0) {
        cycles += array.unit->cycles({trace::Op::Gemm, s, rhs, done, 0, 0}, array.count, backend);
      }
      cycles += s + ceil_div(rhs * s * (s + 1) / 2, lanes);
    }
    return cycles;
  }

  cost::Resources resources(cost::Arithmetic a) const override {
    cost::Datapath d;
    d.macs(params_.lanes, a).divider(1, a);
    d.registers(2.0 * params_.lanes * cost::word_bits(a));
    cost::address_generator(d);
    return d.resources();
  }

 private:
  Params params_;
};

}  // namespace

EDX_REGISTER_COMPONENT(MatrixUnit, Substitution, "substitution",
                       "column-oriented triangular solves on L MAC lanes: trsm, trsv (Table II)");

}  // namespace edx::arch
