// Feature detection, FD (paper Sec. V-B): the FAST-9 segment test (Rosten and Drummond 2006) on
// the FE engine's input stream, lanes = ⌈fe_pixels_per_cycle⌉ pixels a cycle. docs/MODEL.md:
//
//   cycles     stream(pixels + halo, r_fe): the pyramid streams after the halo of its fd_stencil
//              window fills (stencil_halo_pixels)
//   resources  per lane: c±t adders, 16 circle pixels x (brighter, darker) 8-bit comparisons,
//              2 x 16 nine-input ANDs (a contiguous arc at every start), the score (16 |p − c| and
//              their adder tree), 3x3 NMS (8 score comparators); the fd x (fd + lanes − 1) window
//              shift register
//   activity   per pixel c±t (2), 32 compares, 16 |p − c| and the 15-adder score tree (65 pixel
//              operations); 8 NMS compares per candidate; each pixel written to and read from the
//              line buffer once
#include "arch/frontend/frontend_config.hpp"
#include "arch/frontend/task_timing.hpp"

namespace edx::arch {
namespace {

constexpr int kFastCircle = 16;  // Bresenham circle of radius 3
constexpr int kFastArc = 9;      // FAST-9

class Fast final : public FrontendUnit {
 public:
  struct Params {
    static const FieldList<Params>& fields() {
      static const FieldList<Params> list;  // its width follows the FE stream
      return list;
    }
    void validate() const {}
  };
  explicit Fast(const Params& params) : params_(params) {}

  std::string_view kind() const override { return "fast"; }
  nlohmann::json params_json() const override { return params_to_json(params_); }
  trace::Task task() const override { return trace::Task::FD; }
  double stream_pixels_per_cycle(const FrontendConfig& fe) const override {
    return fe.fe_pixels_per_cycle;
  }

  std::int64_t cycles(const trace::TaskRecord& row, std::int64_t,
                      const FrontendConfig& fe) const override {
    if (row.pixels == 0) return 0;
    return stream_cycles(row.pixels + stencil_halo_pixels(row, fe.fd_stencil),
                         fe.fe_pixels_per_cycle);
  }

  cost::Resources resources(const FrontendConfig& fe) const override {
    const int lanes = lanes_of(fe.fe_pixels_per_cycle);
    cost::Datapath d;
    d.adders(lanes * 2, kPixelBits);                     // c + t, c − t
    d.comparators(lanes * 2 * kFastCircle, kPixelBits);  // brighter / darker per circle pixel
    d.reductions(lanes * 2 * kFastCircle, kFastArc);     // 9 contiguous at each of 16 starts
    d.reductions(lanes * 2, 2 * kFastCircle);            // any arc
    d.abs_diffs(lanes * kFastCircle, kPixelBits);        // score: Σ |p − c|
    const int score_bits = d.adder_tree(lanes, kFastCircle, kPixelBits);
    d.comparators(lanes * 8, score_bits);  // 3x3 non-maximum suppression
    d.registers(3.0 * (lanes + 2) * score_bits);
    d.registers(window_bits(fe.fd_stencil, fe.fd_stencil + lanes - 1));
    return d.resources();
  }

  cost::FrameActivity activity(const trace::TaskRecord& row,
                               const FrontendConfig& fe) const override {
    const double px = double(row.pixels);
    cost::FrameActivity a;
    a.int8_ops = 65 * px + 8 * double(row.candidates);
    a.bram_bytes = 2 * px * fe.bytes_per_pixel;
    return a;
  }

 private:
  Params params_;
};

}  // namespace

EDX_REGISTER_COMPONENT(FrontendUnit, Fast, "fast",
                       "FAST-9 segment test on the FE stream: FD (Sec. V-B)");

}  // namespace edx::arch
