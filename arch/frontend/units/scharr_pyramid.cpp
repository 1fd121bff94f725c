// Derivatives calculation, DC (paper Sec. V-B): the LK pyramid (pyrDown, pyramid_filter taps) and
// its Scharr gradients (dc_stencil) streamed at `pixels_per_cycle`, constant coefficients as
// shift-adds. docs/MODEL.md:
//
//   cycles     stream(pixels + halo, pixels_per_cycle) over the LK pyramid
//   resources  per lane Scharr x and y (2 · 2k taps as shift-adds, their trees) and pyrDown (2g
//              taps, their trees); the window shift register
//   activity   2 · 2k + 2g shift-adds a pixel; each pixel written to and read from the line
//              buffer once
#include <algorithm>

#include "arch/common/bounds.hpp"
#include "arch/frontend/frontend_config.hpp"
#include "arch/frontend/task_timing.hpp"

namespace edx::arch {
namespace {

class ScharrPyramid final : public FrontendUnit {
 public:
  struct Params {
    double pixels_per_cycle = 2.0;  ///< the LK pyramid's stream (assumed, as the FE's)
    static const FieldList<Params>& fields() {
      using C = Params;
      static const FieldList<C> list = {
          field("pixels_per_cycle", &C::pixels_per_cycle, "pixels/cycle",
                "derivative (Scharr) stencil over the LK pyramid", bounds::pixels_per_cycle()),
      };
      return list;
    }
    void validate() const { check_fields(*this, "scharr_pyramid", fields()); }
  };
  explicit ScharrPyramid(const Params& params) : params_(params) {}

  std::string_view kind() const override { return "scharr_pyramid"; }
  nlohmann::json params_json() const override { return params_to_json(params_); }
  trace::Task task() const override { return trace::Task::DC; }
  double stream_pixels_per_cycle(const FrontendConfig&) const override {
    return params_.pixels_per_cycle;
  }

  std::int64_t cycles(const trace::TaskRecord& row, std::int64_t,
                      const FrontendConfig& fe) const override {
    if (row.pixels == 0) return 0;
    return stream_cycles(row.pixels + stencil_halo_pixels(row, fe.dc_stencil),
                         params_.pixels_per_cycle);
  }

  cost::Resources resources(const FrontendConfig& fe) const override {
    const int lanes = lanes_of(params_.pixels_per_cycle);
    const int k = fe.dc_stencil;
    const int g = fe.pyramid_filter;
    cost::Datapath d;
    // Scharr: two outputs, 2k non-zero taps each (3, 10, 3 columns), one shift-add per tap.
    d.adders(lanes * 2 * 2 * k, kPixelBits + 5);
    d.adder_tree(2 * lanes, 2 * k, kPixelBits + 5);
    // pyrDown: separable binomial taps, one shift-add per tap and pass.
    d.adders(lanes * 2 * g, kPixelBits + 4);
    d.adder_tree(2 * lanes, g, kPixelBits + 4);
    const int rows = std::max(k, g);
    d.registers(window_bits(rows, rows + lanes - 1));
    return d.resources();
  }

  cost::FrameActivity activity(const trace::TaskRecord& row,
                               const FrontendConfig& fe) const override {
    const double px = double(row.pixels);
    cost::FrameActivity a;
    a.int8_ops = px * (4.0 * fe.dc_stencil + 2.0 * fe.pyramid_filter);
    a.bram_bytes = 2 * px * fe.bytes_per_pixel;
    return a;
  }

 private:
  Params params_;
};

}  // namespace

EDX_REGISTER_COMPONENT(FrontendUnit, ScharrPyramid, "scharr_pyramid",
                       "LK pyramid and Scharr gradients as shift-adds: DC (Sec. V-B)");

}  // namespace edx::arch
