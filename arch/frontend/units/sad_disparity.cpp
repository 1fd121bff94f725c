// Disparity refinement, DR (paper Sec. V-B): block matching of each match's dr_window x dr_window
// window over dr_search offsets along the row (sums of absolute differences), while both images'
// level 0 stream through its stencil buffers. docs/MODEL.md:
//
//   cycles     max(stream(W H, pixels_per_cycle), windows ⌈search / sad_units⌉ window): the
//              image streams (in parallel for the two images) while the SADs of each window's
//              offsets run sad_units at a time, one window row a cycle; 0 without matches
//   resources  sad_units SAD units, each one window row of |L − R| a cycle with its adder tree
//              and accumulator; the argmin over the units, sub-pixel refinement (a parabola
//              through 3 SADs), the window shift registers
//   activity   an |L − R| and an add per window pixel and offset; both windows read from the SBs
#include <algorithm>
#include <cmath>

#include "arch/common/bounds.hpp"
#include "arch/frontend/frontend_config.hpp"
#include "arch/frontend/task_timing.hpp"

namespace edx::arch {
namespace {

class SadDisparity final : public FrontendUnit {
 public:
  struct Params {
    /// Each image's level 0 streamed through its buffers. Calibrated on Edx-Car: 0.25 from the
    /// paper's SM latency (the 44.0 FPS pipelined figure, docs/MODEL.md).
    double pixels_per_cycle = 0.5;
    int sad_units = 11;  ///< window SADs in parallel (one per offset of a ±5 px search)
    static const FieldList<Params>& fields() {
      using C = Params;
      static const FieldList<C> list = {
          field("pixels_per_cycle", &C::pixels_per_cycle, "pixels/cycle",
                "each image's level 0 streamed through DR's buffers", bounds::pixels_per_cycle()),
          field("sad_units", &C::sad_units, "", "window SADs computed in parallel",
                Bounds::at_least(1)),
      };
      return list;
    }
    void validate() const { check_fields(*this, "sad_disparity", fields()); }
  };
  explicit SadDisparity(const Params& params) : params_(params) {}

  std::string_view kind() const override { return "sad_disparity"; }
  nlohmann::json params_json() const override { return params_to_json(params_); }
  trace::Task task() const override { return trace::Task::DR; }
  double stream_pixels_per_cycle(const FrontendConfig&) const override {
    return params_.pixels_per_cycle;
  }

  std::int64_t cycles(const trace::TaskRecord& row, std::int64_t level0_pixels,
                      const FrontendConfig&) const override {
    if (row.keypoints == 0 && row.windows == 0) return 0;
    const std::int64_t stream = stream_cycles(level0_pixels, params_.pixels_per_cycle);
    const std::int64_t offsets = std::max<std::int64_t>(row.search_range, 1);
    const std::int64_t sad = row.windows * ((offsets + params_.sad_units - 1) / params_.sad_units) *
                             std::max<std::int64_t>(row.window_size, 1);
    return std::max(stream, sad);
  }

  cost::Resources resources(const FrontendConfig& fe) const override {
    const int w = fe.dr_window;
    const int units = params_.sad_units;
    cost::Datapath d;
    d.abs_diffs(double(units) * w, kPixelBits);
    const int row_bits = d.adder_tree(units, w, kPixelBits);
    const int sad_bits = row_bits + static_cast<int>(std::ceil(std::log2(w)));
    d.adders(units, sad_bits);                                       // the window's rows
    d.comparators(std::max(0, units - 1), sad_bits);                 // argmin
    d.adders(3, sad_bits + 2).divider(1, cost::Arithmetic::kFixed);  // parabola through 3 SADs
    d.registers(window_bits(w, w) + window_bits(w, w + fe.dr_search - 1));
    return d.resources();
  }

  cost::FrameActivity activity(const trace::TaskRecord& row, const FrontendConfig&) const override {
    const double w2 = double(row.window_size) * double(row.window_size);
    cost::FrameActivity a;
    a.int8_ops = 2 * double(row.windows) * double(row.search_range) * w2;
    a.bram_bytes = 2 * double(row.windows) * double(row.search_range) * w2;
    return a;
  }

 private:
  Params params_;
};

}  // namespace

EDX_REGISTER_COMPONENT(FrontendUnit, SadDisparity, "sad_disparity",
                       "SAD block matching along the row over the streamed images: DR (Sec. V-B)");

}  // namespace edx::arch
