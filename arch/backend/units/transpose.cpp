// The matrix transpose unit (paper Sec. VI-A, Table II "Matrix Transpose"): moves w words a cycle
// (one SPM read and write port pair per word). docs/MODEL.md ("Backend accelerator"):
//
//   transpose m x n  ⌈m n / (w c)⌉ on c copies
//   resources        a w x w tile of word registers read across, a w:w crossbar, an address
//                    generator (no arithmetic)
#include "arch/backend/matrix_unit.hpp"
#include "arch/backend/op_timing.hpp"
#include "arch/common/bounds.hpp"

namespace edx::arch {
namespace {

class Transpose final : public MatrixUnit {
 public:
  struct Params {
    int words_per_cycle = 4;  ///< w (assumed)
    static const FieldList<Params>& fields() {
      using C = Params;
      static const FieldList<C> list = {
          field("words_per_cycle", &C::words_per_cycle, "words/cycle",
                "w: words moved a cycle (Edx-Car: 4)", bounds::ops_per_cycle()),
      };
      return list;
    }
    void validate() const { check_fields(*this, "transpose", fields()); }
  };
  explicit Transpose(const Params& params) : params_(params) {}

  std::string_view kind() const override { return "transpose"; }
  nlohmann::json params_json() const override { return params_to_json(params_); }
  bool serves(trace::Op op) const override { return op == trace::Op::Transpose; }
  std::string building_block() const override { return "transpose (moves words, no arithmetic)"; }
  double mac_lanes() const override { return 0.0; }

  std::int64_t cycles(const trace::OpRecord& op, int copies, const BackendConfig&) const override {
    return ceil_div(op.m * op.n, std::int64_t(params_.words_per_cycle) * std::max(1, copies));
  }

  cost::Resources resources(cost::Arithmetic a) const override {
    const int w = params_.words_per_cycle;
    cost::Datapath d;
    d.registers(double(w) * w * cost::word_bits(a));  // a w x w tile, read across
    d.muxes(w, cost::word_bits(a), w);
    cost::address_generator(d);
    return d.resources();
  }

 private:
  Params params_;
};

}  // namespace

EDX_REGISTER_COMPONENT(MatrixUnit, Transpose, "transpose",
                       "moves w words a cycle between SPM ports: transpose (Table II)");

}  // namespace edx::arch
