// The matrix multiplication unit (paper Sec. VI-A, Table II): a b x b output-stationary systolic
// array. docs/MODEL.md ("Backend accelerator") lists its formulas:
//
//   tiles(m, n)    ⌈m/b⌉ ⌈n/b⌉ result tiles; with a symmetric result (symmetric_optimization) only
//                  the T(T+1)/2 on and above the diagonal, T = ⌈m/b⌉
//   array(T, k)    T (k + 2b): each tile accumulates k products after its 2b fill and drain
//                  (operands skewed into b rows and columns, results shifted out), or with
//                  overlap_tiles T max(k, b) + 2b (the next tile streams in while the previous one
//                  drains; a tile cannot drain faster than its b results a column take to shift
//                  out). 0 when T or k is 0.
//   gemm m x n x k  array(⌈tiles(m, n) / c⌉, k) on c copies (the tiles dealt out over them);
//                  transposed operands (kTransposeA/B) cost nothing (the address generator reads
//                  them transposed); a symmetric result counts only the upper tiles
//   syrk m x m of k the same with n = m, the result always symmetric
//   a batch of B instances: their B · tiles(m, n) result tiles stream through the array as one
//                  op's (with overlap_tiles one fill and drain for the batch)
//   resources      b^2 MACs with their operand registers, b-wide input registers, an address
//                  generator
#include <algorithm>

#include "arch/backend/matrix_unit.hpp"
#include "arch/backend/op_timing.hpp"

namespace edx::arch {
namespace {

class SystolicArray final : public MatrixUnit {
 public:
  struct Params {
    int block = 4;               ///< b (assumed: Table III's DSP budget, docs/MODEL.md)
    bool overlap_tiles = false;  ///< double-buffered accumulators (assumed)
    static const FieldList<Params>& fields();
    void validate() const;
  };
  explicit SystolicArray(const Params& params) : params_(params) {}
  const Params& params() const { return params_; }

  std::string_view kind() const override { return "systolic_array"; }
  nlohmann::json params_json() const override { return params_to_json(params_); }
  bool serves(trace::Op op) const override {
    return op == trace::Op::Gemm || op == trace::Op::Syrk;
  }
  std::string building_block() const override { return "matrix multiplication (b x b array)"; }
  std::int64_t cycles(const trace::OpRecord& op, int copies,
                      const BackendConfig& backend) const override {
    return cycles_of(op, 1, copies, backend);
  }
  std::int64_t batch_cycles(const trace::OpRecord& op, int copies,
                            const BackendConfig& backend) const override {
    return cycles_of(op, op.batch, copies, backend);
  }
  double mac_lanes() const override { return double(params_.block) * params_.block; }
  cost::Resources resources(cost::Arithmetic arithmetic) const override;
  int tile() const override { return params_.block; }

  /// Result tiles of an m x n result (the upper ones only when `symmetric_result`).
  std::int64_t tiles(std::int64_t m, std::int64_t n, bool symmetric_result) const;
  /// Cycles of `tiles` output tiles accumulating k products each (see above).
  std::int64_t array_cycles(std::int64_t tiles, std::int64_t k) const;

 private:
  /// Cycles of `instances` instances of `op`, their result tiles dealt out over the copies.
  std::int64_t cycles_of(const trace::OpRecord& op, std::int64_t instances, int copies,
                         const BackendConfig& backend) const;

  Params params_;
};

const FieldList<SystolicArray::Params>& SystolicArray::Params::fields() {
  using C = Params;
  static const FieldList<C> list = {
      field("block", &C::block, "",
            "b: the array is b x b processing elements, b^2 MACs a cycle (Edx-Car: 4, Table "
            "III's DSP budget)",
            Bounds::at_least(1).at_most(256)),
      field("overlap_tiles", &C::overlap_tiles, "",
            "double-buffered accumulators: fill and drain paid once per op, not per tile"),
  };
  return list;
}

void SystolicArray::Params::validate() const { check_fields(*this, "systolic_array", fields()); }

std::int64_t SystolicArray::tiles(std::int64_t m, std::int64_t n, bool symmetric_result) const {
  const std::int64_t rows = ceil_div(m, params_.block);
  if (symmetric_result) return rows * (rows + 1) / 2;  // tiles on and above the diagonal
  return rows * ceil_div(n, params_.block);
}

std::int64_t SystolicArray::array_cycles(std::int64_t tiles, std::int64_t k) const {
  if (tiles == 0 || k == 0) return 0;
  const std::int64_t b = params_.block;
  if (params_.overlap_tiles) return tiles * std::max(k, b) + 2 * b;
  return tiles * (k + 2 * b);
}

std::int64_t SystolicArray::cycles_of(const trace::OpRecord& op, std::int64_t instances, int copies,
                                      const BackendConfig& backend) const {
  const bool syrk = op.op == trace::Op::Syrk;
  if (op.m == 0 || op.k == 0 || (!syrk && op.n == 0)) return 0;
  const bool symmetric = backend.symmetric_optimization && (syrk || symmetric_gemm_result(op));
  // The result's tiles are dealt out over the copies: each computes ⌈T / c⌉ of them.
  const std::int64_t all = instances * tiles(op.m, syrk ? op.m : op.n, symmetric);
  return array_cycles(ceil_div(all, std::max(1, copies)), op.k);
}

cost::Resources SystolicArray::resources(cost::Arithmetic a) const {
  const double pes = double(params_.block) * params_.block;
  cost::Datapath d;
  d.macs(pes, a);
  d.registers(pes * 2 * cost::word_bits(a));              // operands passed along rows, columns
  d.registers(2.0 * params_.block * cost::word_bits(a));  // block row / column inputs
  cost::address_generator(d);
  return d.resources();
}

}  // namespace

EDX_REGISTER_COMPONENT(MatrixUnit, SystolicArray, "systolic_array",
                       "b x b output-stationary array of MACs: gemm, syrk (Table II)");

}  // namespace edx::arch
