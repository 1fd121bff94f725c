// A frontend unit kind added by a test in one file, as a user would add one (issue 40): a corner
// detector for FD that streams its image at its own rate through a w x w window:
//   cycles     stream(pixels + halo(w), pixels_per_cycle)
//   resources  per lane w^2 8-bit products for the structure tensor and its window register
//   activity   3 w^2 pixel operations a pixel
#include "arch/frontend/frontend_config.hpp"
#include "arch/frontend/task_timing.hpp"

namespace edx::arch {
namespace {

class HarrisDetector final : public FrontendUnit {
 public:
  struct Params {
    double pixels_per_cycle = 1;  ///< its own stream rate
    int window = 5;               ///< w
    static const FieldList<Params>& fields() {
      using C = Params;
      static const FieldList<C> list = {
          field("pixels_per_cycle", &C::pixels_per_cycle, "pixels/cycle", "its stream rate",
                Bounds::above(0)),
          field("window", &C::window, "pixels", "the structure tensor's window side",
                Bounds::at_least(3).odd_only()),
      };
      return list;
    }
    void validate() const { check_fields(*this, "harris_detector", fields()); }
  };
  explicit HarrisDetector(const Params& params) : params_(params) {}

  std::string_view kind() const override { return "harris_detector"; }
  nlohmann::json params_json() const override { return params_to_json(params_); }
  trace::Task task() const override { return trace::Task::FD; }
  double stream_pixels_per_cycle(const FrontendConfig&) const override {
    return params_.pixels_per_cycle;
  }

  std::int64_t cycles(const trace::TaskRecord& row, std::int64_t,
                      const FrontendConfig&) const override {
    if (row.pixels == 0) return 0;
    return stream_cycles(row.pixels + stencil_halo_pixels(row, params_.window),
                         params_.pixels_per_cycle);
  }

  cost::Resources resources(const FrontendConfig&) const override {
    const int lanes = lanes_of(params_.pixels_per_cycle);
    const int w = params_.window;
    cost::Datapath d;
    d.multipliers(double(lanes) * w * w, kPixelBits, kPixelBits);
    d.registers(window_bits(w, w + lanes - 1));
    return d.resources();
  }

  cost::FrameActivity activity(const trace::TaskRecord& row, const FrontendConfig&) const override {
    cost::FrameActivity a;
    a.int8_ops = 3.0 * params_.window * params_.window * double(row.pixels);
    return a;
  }

 private:
  Params params_;
};

}  // namespace

EDX_REGISTER_COMPONENT(FrontendUnit, HarrisDetector, "harris_detector",
                       "a test's Harris corner detector on its own stream: FD");

}  // namespace edx::arch
