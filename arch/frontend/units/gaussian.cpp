// Image filtering, IF (paper Sec. V-B): the k x k Gaussian (k = if_stencil, or the trace row's
// window) on the FE engine's input stream, lanes = ⌈fe_pixels_per_cycle⌉. docs/MODEL.md:
//
//   cycles     stream(pixels + halo, r_fe)
//   resources  per lane k^2 MACs (2k when separable) of `arithmetic` (fixed point: one DSP each
//              and the adder tree of the products; single: PG060 operators), the window shift
//              register (and the column results when separable)
//   activity   k^2 MACs a pixel
#include "arch/frontend/frontend_config.hpp"
#include "arch/frontend/task_timing.hpp"

namespace edx::arch {
namespace {

class Gaussian final : public FrontendUnit {
 public:
  struct Params {
    /// Its MACs: "fixed" (one DSP each) or "single" (PG060). Selected against Table III
    /// (docs/MODEL.md): single precision brings the DSP within 12 % uncalibrated.
    std::string arithmetic = "single";
    bool separable = false;  ///< two 1-D passes (2k taps) instead of k^2
    static const FieldList<Params>& fields() {
      using C = Params;
      static const FieldList<C> list = {
          choice_field("arithmetic", &C::arithmetic, "", {"fixed", "single"},
                       "its multiply-accumulates: fixed point (one DSP) or single precision "
                       "(selected against Table III)"),
          field("separable", &C::separable, "", "two 1-D passes (2k taps) instead of k^2"),
      };
      return list;
    }
    void validate() const { check_fields(*this, "gaussian", fields()); }
  };
  explicit Gaussian(const Params& params)
      : params_(params), arithmetic_(cost::parse_arithmetic(params.arithmetic, "arithmetic")) {}

  std::string_view kind() const override { return "gaussian"; }
  nlohmann::json params_json() const override { return params_to_json(params_); }
  trace::Task task() const override { return trace::Task::IF; }
  double stream_pixels_per_cycle(const FrontendConfig& fe) const override {
    return fe.fe_pixels_per_cycle;
  }

  std::int64_t cycles(const trace::TaskRecord& row, std::int64_t,
                      const FrontendConfig& fe) const override {
    if (row.pixels == 0) return 0;
    return stream_cycles(row.pixels + stencil_halo_pixels(row, stencil_of(row, fe.if_stencil)),
                         fe.fe_pixels_per_cycle);
  }

  cost::Resources resources(const FrontendConfig& fe) const override {
    const int lanes = lanes_of(fe.fe_pixels_per_cycle);
    const int k = fe.if_stencil;
    const int taps = params_.separable ? 2 * k : k * k;
    cost::Datapath d;
    d.macs(lanes * taps, arithmetic_, kPixelBits, 16);
    if (arithmetic_ == cost::Arithmetic::kFixed) d.adder_tree(lanes, taps, kPixelBits + 16);
    d.registers(window_bits(k, k + lanes - 1));
    if (params_.separable) d.registers(double(k) * lanes * (kPixelBits + 16));  // column results
    return d.resources();
  }

  cost::FrameActivity activity(const trace::TaskRecord& row,
                               const FrontendConfig& fe) const override {
    // k² taps a pixel (k: the trace's window_size, else if_stencil); FD's line buffer.
    const double px = double(row.pixels);
    const double k = row.window_size > 0 ? double(row.window_size) : double(fe.if_stencil);
    cost::FrameActivity a;
    (arithmetic_ == cost::Arithmetic::kSingle ? a.single_macs : a.fixed_macs) = px * k * k;
    return a;
  }

 private:
  Params params_;
  cost::Arithmetic arithmetic_;
};

}  // namespace

EDX_REGISTER_COMPONENT(FrontendUnit, Gaussian, "gaussian",
                       "k x k Gaussian on the FE stream: IF (Sec. V-B)");

}  // namespace edx::arch
