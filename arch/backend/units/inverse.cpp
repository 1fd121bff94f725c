// The matrix inverse unit (paper Sec. VI-A, Table II "Matrix Inverse"): reciprocal and
// multiply-accumulate lanes, specialized (structured: true) for A_mm = [A B; B^T D] with A
// diagonal and D the 6x6 pose block, which SLAM's marginalization inverts ("the inversion hardware
// is specialized for a 6 x 6 matrix inversion combined with simple reciprocal structures").
// docs/MODEL.md ("Backend accelerator") lists its formulas; L lanes, c copies, d = m - 6:
//
//   general     m t_div + ⌈m^3 / (L c)⌉: Gauss-Jordan, each pivot's reciprocal on the critical
//               path, n rows of n updated per pivot
//   diagonal    (flag kDiagonal: SLAM's Schur complement's H_ll) t_div + ⌈m / (L c)⌉: the
//               reciprocals, pipelined over the lanes; m scalars in and out, no multiply-adds
//   structured  (flags kDiagonalBlock and kBlock6x6, m > 6; workloads/backend/slam/
//               marginalizer.cpp computes the full symmetric inverse this way)
//                 reciprocals of the diagonal, pipelined over the lanes   t_div + ⌈d / (L c)⌉
//                 S^-1 of the 6x6 Schur complement, Gauss-Jordan          general(6)
//                 products: A^-1 B (6d), S = D - B^T A^-1 B (36d), A^-1 B S^-1 (36d), the dense
//                 top-left block (A^-1 B S^-1)(A^-1 B)^T + A^-1 (6 sym(d))  ⌈(78d + 6 sym(d)) / (L
//                 c)⌉
//               its operands in the SPM are the blocks: in d + 6d + sym(6), out sym(m); its
//               multiply-adds 78d + 6 sym(d)
//   resources   one divider, L MACs, operand registers, an address generator
#include "arch/backend/matrix_unit.hpp"
#include "arch/backend/op_timing.hpp"
#include "arch/common/bounds.hpp"

namespace edx::arch {
namespace {

namespace flags = trace::op_flags;

class Inverse final : public MatrixUnit {
 public:
  struct Params {
    int lanes = 1;                   ///< L (assumed; Table III's DSP budget, docs/MODEL.md)
    bool structured = true;          ///< the diagonal + 6x6 specialization (Sec. VI-A)
    int divide_latency_cycles = 30;  ///< pipelined double divider (assumed)
    static const FieldList<Params>& fields() {
      using C = Params;
      const Bounds positive = Bounds::at_least(1);
      static const FieldList<C> list = {
          field("lanes", &C::lanes, "", "multiply-accumulate lanes (Edx-Car: 1)", positive),
          field("structured", &C::structured, "",
                "invert [A B; B^T D] with A diagonal and D 6x6 as reciprocals + a 6x6 inverse"),
          field("divide_latency_cycles", &C::divide_latency_cycles, "cycles",
                "latency of its pipelined divider (a reciprocal per pivot)",
                bounds::latency_cycles()),
      };
      return list;
    }
    void validate() const { check_fields(*this, "inverse", fields()); }
  };
  explicit Inverse(const Params& params) : params_(params) {}

  std::string_view kind() const override { return "inverse"; }
  nlohmann::json params_json() const override { return params_to_json(params_); }
  bool serves(trace::Op op) const override { return op == trace::Op::Inverse; }
  std::string building_block() const override { return "inverse (diagonal + 6x6 structured)"; }
  double mac_lanes() const override { return params_.lanes; }

  std::int64_t cycles(const trace::OpRecord& op, int copies,
                      const BackendConfig& backend) const override {
    if (op.m == 0) return 0;
    const std::int64_t lanes = std::int64_t(params_.lanes) * std::max(1, copies);
    if (diagonal(op)) return params_.divide_latency_cycles + ceil_div(op.m, lanes);
    if (!structured(op)) return general_cycles(op.m, lanes);
    const std::int64_t d = op.m - kPoseBlock;  // diagonal (landmark) part
    const std::int64_t reciprocals = params_.divide_latency_cycles + ceil_div(d, lanes);
    return reciprocals + general_cycles(kPoseBlock, lanes) +
           ceil_div(structured_products(d, backend), lanes);
  }

  std::optional<OperandScalars> own_operands(const trace::OpRecord& op,
                                             const BackendConfig& backend) const override {
    if (diagonal(op)) return OperandScalars{op.m, op.m};
    if (!structured(op)) return std::nullopt;
    const std::int64_t d = op.m - kPoseBlock;
    return OperandScalars{d + d * kPoseBlock + symmetric_scalars(kPoseBlock, backend),
                          symmetric_scalars(op.m, backend)};
  }

  std::optional<std::int64_t> own_macs(const trace::OpRecord& op,
                                       const BackendConfig& backend) const override {
    if (diagonal(op)) return 0;
    if (!structured(op)) return std::nullopt;
    return structured_products(op.m - kPoseBlock, backend);
  }

  cost::Resources resources(cost::Arithmetic a) const override {
    cost::Datapath d;
    d.divider(1, a).macs(params_.lanes, a);
    d.registers(2.0 * params_.lanes * cost::word_bits(a));
    cost::address_generator(d);
    return d.resources();
  }

 private:
  /// A diagonal matrix: its inverse is its reciprocals.
  static bool diagonal(const trace::OpRecord& op) { return (op.flags & flags::kDiagonal) != 0; }
  /// The structured form serves `op`: flags kDiagonalBlock and kBlock6x6, m > 6, structured on.
  bool structured(const trace::OpRecord& op) const {
    return params_.structured && (op.flags & flags::kDiagonalBlock) &&
           (op.flags & flags::kBlock6x6) && op.m > kPoseBlock;
  }
  std::int64_t general_cycles(std::int64_t n, std::int64_t lanes) const {
    return n * params_.divide_latency_cycles + ceil_div(n * n * n, lanes);
  }
  /// A^-1 B (6d) + B^T A^-1 B (36d) + A^-1 B S^-1 (36d) + the top-left block (6 per entry).
  static std::int64_t structured_products(std::int64_t d, const BackendConfig& backend) {
    return 78 * d + kPoseBlock * symmetric_scalars(d, backend);
  }

  Params params_;
};

}  // namespace

EDX_REGISTER_COMPONENT(MatrixUnit, Inverse, "inverse",
                       "Gauss-Jordan and the diagonal + 6x6 structured inverse on L MAC lanes: "
                       "inverse (Table II)");

}  // namespace edx::arch
