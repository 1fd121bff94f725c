// A backend unit kind added by a test in one file, as a user would add one (issue 40): a vector of
// L multiply-accumulate lanes serving gemm and syrk, fed one product per lane a cycle through a
// pipeline d cycles deep:
//   cycles     ⌈m n k / (L c)⌉ + d on c copies (syrk: its k sym(m) products)
//   resources  L MACs of the unit's precision, their operand registers, an address generator
#include "arch/backend/matrix_unit.hpp"
#include "arch/backend/op_timing.hpp"

namespace edx::arch {
namespace {

class VectorMac final : public MatrixUnit {
 public:
  struct Params {
    int lanes = 4;  ///< L
    int depth = 6;  ///< d: the MAC pipeline's fill
    static const FieldList<Params>& fields() {
      using C = Params;
      static const FieldList<C> list = {
          field("lanes", &C::lanes, "", "multiply-accumulate lanes", Bounds::at_least(1)),
          field("depth", &C::depth, "cycles", "pipeline fill of one op", Bounds::at_least(0)),
      };
      return list;
    }
    void validate() const { check_fields(*this, "vector_mac", fields()); }
  };
  explicit VectorMac(const Params& params) : params_(params) {}

  std::string_view kind() const override { return "vector_mac"; }
  nlohmann::json params_json() const override { return params_to_json(params_); }
  bool serves(trace::Op op) const override {
    return op == trace::Op::Gemm || op == trace::Op::Syrk;
  }
  std::string building_block() const override { return "matrix multiplication (MAC vector)"; }
  double mac_lanes() const override { return params_.lanes; }

  std::int64_t cycles(const trace::OpRecord& op, int copies,
                      const BackendConfig& backend) const override {
    const std::int64_t products = op_macs(op, backend);
    if (products == 0) return 0;
    return ceil_div(products, std::int64_t(params_.lanes) * copies) + params_.depth;
  }

  cost::Resources resources(cost::Arithmetic arithmetic) const override {
    cost::Datapath d;
    d.macs(params_.lanes, arithmetic);
    d.registers(2.0 * params_.lanes * cost::word_bits(arithmetic));
    cost::address_generator(d);
    return d.resources();
  }

 private:
  Params params_;
};

}  // namespace

EDX_REGISTER_COMPONENT(MatrixUnit, VectorMac, "vector_mac",
                       "a test's L-lane MAC vector: gemm, syrk");

}  // namespace edx::arch
