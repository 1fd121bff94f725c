// Least-squares solving, LSS (paper Sec. V-B): the Lucas-Kanade Gauss-Newton updates of each
// tracked point on `macs_per_cycle` multiply-accumulates (Bouguet 2001, OpenCV's LK).
// docs/MODEL.md:
//
//   cycles     ⌈w^2 (9 iterations + 3 points) / macs⌉: per update and window pixel 5 products
//              for the normal equations and mismatch (Ix², IxIy, Iy², IxIt, IyIt) and 4 for the
//              bilinear interpolation of the moved window; per point solve 3 for its window's
//              gradient matrix
//   resources  macs_per_cycle MACs (16 x 16 bits fixed, or PG060 single), five accumulators, the
//              2x2 solve of a step (4 multiplies, 2 adds, 1 divide in single precision)
//   activity   the same MACs; I, Ix, Iy read from the SPM per window pixel and update
#include "arch/common/bounds.hpp"
#include "arch/frontend/frontend_config.hpp"
#include "arch/frontend/task_timing.hpp"

namespace edx::arch {
namespace {

constexpr std::int64_t kProductsPerIteration = 9;
constexpr std::int64_t kProductsPerPoint = 3;

class LkSolver final : public FrontendUnit {
 public:
  struct Params {
    int macs_per_cycle = 64;            ///< (assumed)
    std::string arithmetic = "single";  ///< selected against Table III, as IF's
    static const FieldList<Params>& fields() {
      using C = Params;
      static const FieldList<C> list = {
          field("macs_per_cycle", &C::macs_per_cycle, "MACs/cycle",
                "multiply-accumulates a cycle of the LK solver", bounds::ops_per_cycle()),
          choice_field("arithmetic", &C::arithmetic, "", {"fixed", "single"},
                       "its multiply-accumulates: fixed point (16 x 16 bits) or single precision "
                       "(selected against Table III)"),
      };
      return list;
    }
    void validate() const { check_fields(*this, "lk_solver", fields()); }
  };
  explicit LkSolver(const Params& params)
      : params_(params), arithmetic_(cost::parse_arithmetic(params.arithmetic, "arithmetic")) {}

  std::string_view kind() const override { return "lk_solver"; }
  nlohmann::json params_json() const override { return params_to_json(params_); }
  trace::Task task() const override { return trace::Task::LSS; }
  double stream_pixels_per_cycle(const FrontendConfig&) const override { return 0.0; }

  std::int64_t cycles(const trace::TaskRecord& row, std::int64_t,
                      const FrontendConfig&) const override {
    const std::int64_t window = row.window_size * row.window_size;
    const std::int64_t products =
        window * (kProductsPerIteration * row.iterations + kProductsPerPoint * row.points);
    return (products + params_.macs_per_cycle - 1) / params_.macs_per_cycle;
  }

  cost::Resources resources(const FrontendConfig&) const override {
    cost::Datapath d;
    d.macs(params_.macs_per_cycle, arithmetic_, 16, 16);
    d.registers(5 * 32);  // Σ Ix², Σ IxIy, Σ Iy², Σ Ix·dt, Σ Iy·dt
    d.fp(4, cost::kSingleMultiply).fp(2, cost::kSingleAdd).fp(1, cost::kSingleDivide);
    return d.resources();
  }

  cost::FrameActivity activity(const trace::TaskRecord& row, const FrontendConfig&) const override {
    const double w2 = double(row.window_size) * double(row.window_size);
    const double work = w2 * (9.0 * double(row.iterations) + 3.0 * double(row.points));
    cost::FrameActivity a;
    (arithmetic_ == cost::Arithmetic::kSingle ? a.single_macs : a.fixed_macs) = work;
    a.bram_bytes = 3 * w2 * double(row.iterations + row.points);
    return a;
  }

 private:
  Params params_;
  cost::Arithmetic arithmetic_;
};

}  // namespace

EDX_REGISTER_COMPONENT(FrontendUnit, LkSolver, "lk_solver",
                       "Lucas-Kanade Gauss-Newton steps on MAC lanes: LSS (Sec. V-B)");

}  // namespace edx::arch
