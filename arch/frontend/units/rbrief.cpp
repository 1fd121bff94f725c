// Descriptor calculation, FC (paper Sec. V-B): the rBRIEF descriptor of each keypoint (Rublee et
// al. 2011): its orientation by intensity moments over the fc_patch x fc_patch patch, then 256
// intensity tests of the rotated pattern. docs/MODEL.md:
//
//   cycles     descriptors (⌈p / rows⌉ + ⌈256 / tests⌉), p the patch side (the trace row's)
//   resources  orientation over `patch_rows_per_cycle` rows a cycle (per row: x·I products and
//              their tree, the row sum tree, one y·rowsum product, two accumulators; a 16-stage
//              CORDIC atan2), `tests_per_cycle` tests (two patch²:1 pixel muxes and a comparator
//              each) from the patch² window register, the rotated-pattern table in BRAM
//              (angle_bins x 256 pairs)
//   activity   2 p^2 moment products and 256 tests a descriptor (pixel operations), the patch
//              read from the SB
#include <cmath>

#include "arch/common/bounds.hpp"
#include "arch/frontend/frontend_config.hpp"
#include "arch/frontend/task_timing.hpp"
#include "arch/memory/bram.hpp"

namespace edx::arch {
namespace {

constexpr std::int64_t kBriefTests = 256;  // rBRIEF compares 256 pixel pairs a descriptor
constexpr int kDescriptorBits = 256;       // one bit a test
constexpr int kCordicStages = 16;

class Rbrief final : public FrontendUnit {
 public:
  struct Params {
    int patch_rows_per_cycle = 1;  ///< orientation: patch rows of moments a cycle (assumed)
    int tests_per_cycle = 32;      ///< rBRIEF intensity tests a cycle (assumed)
    int angle_bins = 30;           ///< the rotated-pattern table (ORB: 12 degrees)
    static const FieldList<Params>& fields() {
      using C = Params;
      const Bounds count = Bounds::at_least(1);
      static const FieldList<C> list = {
          field("patch_rows_per_cycle", &C::patch_rows_per_cycle, "rows/cycle",
                "orientation: patch rows of moments a cycle (at most a patch's)",
                bounds::window_side()),
          field("tests_per_cycle", &C::tests_per_cycle, "tests/cycle",
                "rBRIEF intensity tests a cycle (256 per descriptor: more do nothing)",
                Bounds::at_least(1).at_most(256)),
          field("angle_bins", &C::angle_bins, "", "rBRIEF's rotated-pattern table entries", count),
      };
      return list;
    }
    void validate() const { check_fields(*this, "rbrief", fields()); }
  };
  explicit Rbrief(const Params& params) : params_(params) {}

  std::string_view kind() const override { return "rbrief"; }
  nlohmann::json params_json() const override { return params_to_json(params_); }
  trace::Task task() const override { return trace::Task::FC; }
  double stream_pixels_per_cycle(const FrontendConfig&) const override { return 0.0; }

  std::int64_t cycles(const trace::TaskRecord& row, std::int64_t,
                      const FrontendConfig& fe) const override {
    const std::int64_t patch = stencil_of(row, fe.fc_patch);
    const std::int64_t per_descriptor =
        (patch + params_.patch_rows_per_cycle - 1) / params_.patch_rows_per_cycle +
        (kBriefTests + params_.tests_per_cycle - 1) / params_.tests_per_cycle;
    return row.descriptors * per_descriptor;
  }

  cost::Resources resources(const FrontendConfig& fe) const override {
    const int patch = fe.fc_patch;
    const int rows = params_.patch_rows_per_cycle;
    const int tests = params_.tests_per_cycle;
    const int coordinate_bits = static_cast<int>(std::ceil(std::log2(patch)));
    cost::Datapath d;
    // Orientation: m10 = Σ x·I, m01 = Σ y·(Σ_x I), per patch row a cycle.
    d.multipliers(double(rows) * patch, kPixelBits, coordinate_bits);
    const int product_sum = d.adder_tree(rows, patch, kPixelBits + coordinate_bits);
    const int row_sum = d.adder_tree(rows, patch, kPixelBits);
    d.multipliers(rows, row_sum, coordinate_bits);
    d.adders(2, std::max(product_sum, row_sum + coordinate_bits) + coordinate_bits);
    d.adders(3 * kCordicStages, 20);  // unrolled CORDIC atan2 of the moments
    // Tests: two arbitrary patch pixels each, compared.
    d.muxes(2.0 * tests, kPixelBits, patch * patch);
    d.comparators(tests, kPixelBits);
    d.registers(kDescriptorBits);
    d.registers(window_bits(patch, patch));  // the patch the muxes select from (fc.L<l> SB)
    // Rotated test pattern: angle bins x 256 tests x (2 points x 2 coordinates) of 6 bits.
    const auto rom =
        map_to_bram(tests * 24, std::int64_t(params_.angle_bins) * kDescriptorBits / tests);
    d.bram(rom.blocks);
    return d.resources();
  }

  cost::FrameActivity activity(const trace::TaskRecord& row,
                               const FrontendConfig& fe) const override {
    cost::FrameActivity a;
    a.int8_ops = double(row.descriptors) * (2.0 * fe.fc_patch * fe.fc_patch + 256);
    a.bram_bytes = double(row.descriptors) * fe.fc_patch * fe.fc_patch;
    return a;
  }

 private:
  Params params_;
};

}  // namespace

EDX_REGISTER_COMPONENT(FrontendUnit, Rbrief, "rbrief",
                       "rBRIEF orientation and 256 tests a keypoint: FC (Sec. V-B)");

}  // namespace edx::arch
