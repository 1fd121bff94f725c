#include "arch/cost/unit_costs.hpp"

#include <cmath>

#include "arch/memory/bram.hpp"

namespace edx::arch::cost {
namespace {

constexpr int kPixelBits = 8;
constexpr int kDescriptorBits = 256;  // rBRIEF
constexpr int kFastCircle = 16;       // Bresenham circle of radius 3
constexpr int kFastArc = 9;           // FAST-9
constexpr int kCordicStages = 16;

/// A k-row window of `columns` pixels held in flip-flops (the SB's shift register).
double window_bits(int rows, int columns) { return double(rows) * columns * kPixelBits; }

}  // namespace

int lanes_of(double pixels_per_cycle) {
  return std::max(1, static_cast<int>(std::ceil(pixels_per_cycle - 1e-9)));
}

Resources fd_cost(const FrontendConfig& fe) {
  const int lanes = lanes_of(fe.fe_pixels_per_cycle);
  Datapath d;
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

Resources if_cost(const FrontendConfig& fe, const CostConfig& cost) {
  const int lanes = lanes_of(fe.fe_pixels_per_cycle);
  const int k = fe.if_stencil;
  const int taps = cost.if_separable ? 2 * k : k * k;
  Datapath d;
  d.macs(lanes * taps, cost.frontend_arith(), kPixelBits, 16);
  if (cost.frontend_arith() == Arithmetic::kFixed) d.adder_tree(lanes, taps, kPixelBits + 16);
  d.registers(window_bits(k, k + lanes - 1));
  if (cost.if_separable) d.registers(double(k) * lanes * (kPixelBits + 16));  // column results
  return d.resources();
}

Resources fc_cost(const FrontendConfig& fe, const CostConfig& cost) {
  const int patch = fe.fc_patch;
  const int rows = fe.fc_patch_rows_per_cycle;
  const int coordinate_bits = static_cast<int>(std::ceil(std::log2(patch)));
  Datapath d;
  // Orientation: m10 = Σ x·I, m01 = Σ y·(Σ_x I), per patch row a cycle.
  d.multipliers(double(rows) * patch, kPixelBits, coordinate_bits);
  const int product_sum = d.adder_tree(rows, patch, kPixelBits + coordinate_bits);
  const int row_sum = d.adder_tree(rows, patch, kPixelBits);
  d.multipliers(rows, row_sum, coordinate_bits);
  d.adders(2, std::max(product_sum, row_sum + coordinate_bits) + coordinate_bits);
  d.adders(3 * kCordicStages, 20);  // unrolled CORDIC atan2 of the moments
  // Tests: two arbitrary patch pixels each, compared.
  d.muxes(2.0 * fe.fc_tests_per_cycle, kPixelBits, patch * patch);
  d.comparators(fe.fc_tests_per_cycle, kPixelBits);
  d.registers(kDescriptorBits);
  d.registers(window_bits(patch, patch));  // the patch the muxes select from (fc.L<l> SB)
  // Rotated test pattern: angle bins x 256 tests x (2 points x 2 coordinates) of 6 bits.
  const auto rom =
      map_to_bram(fe.fc_tests_per_cycle * 24,
                  std::int64_t(cost.fc_angle_bins) * kDescriptorBits / fe.fc_tests_per_cycle);
  d.bram(rom.blocks);
  return d.resources();
}

Resources mo_cost(const FrontendConfig& fe) {
  const int distance_bits = static_cast<int>(std::log2(kDescriptorBits)) + 1;
  Datapath d;
  d.xors(fe.mo_comparators, kDescriptorBits);
  d.popcounts(fe.mo_comparators, kDescriptorBits);
  d.comparators(2.0 * fe.mo_comparators, distance_bits);  // best and second best
  d.registers(2.0 * kDescriptorBits + 4.0 * fe.mo_comparators * (distance_bits + 16));
  return d.resources();
}

Resources dr_cost(const FrontendConfig& fe) {
  const int w = fe.dr_window;
  Datapath d;
  d.abs_diffs(double(fe.dr_sad_units) * w, kPixelBits);
  const int row_bits = d.adder_tree(fe.dr_sad_units, w, kPixelBits);
  const int sad_bits = row_bits + static_cast<int>(std::ceil(std::log2(w)));
  d.adders(fe.dr_sad_units, sad_bits);                        // accumulate the window's rows
  d.comparators(std::max(0, fe.dr_sad_units - 1), sad_bits);  // argmin
  d.adders(3, sad_bits + 2).divider(1, Arithmetic::kFixed);   // parabola through 3 SADs
  d.registers(window_bits(w, w) + window_bits(w, w + fe.dr_search - 1));
  return d.resources();
}

Resources dc_cost(const FrontendConfig& fe) {
  const int lanes = lanes_of(fe.dc_pixels_per_cycle);
  const int k = fe.dc_stencil;
  const int g = fe.pyramid_filter;
  Datapath d;
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

Resources lss_cost(const FrontendConfig& fe, const CostConfig& cost) {
  Datapath d;
  d.macs(fe.lss_macs_per_cycle, cost.frontend_arith(), 16, 16);
  d.registers(5 * 32);  // Σ Ix², Σ IxIy, Σ Iy², Σ Ix·dt, Σ Iy·dt
  d.fp(4, kSingleMultiply).fp(2, kSingleAdd).fp(1, kSingleDivide);  // 2x2 solve
  return d.resources();
}

Arithmetic backend_arithmetic(const BackendConfig& be) {
  return be.scalar_bytes == 4 ? Arithmetic::kSingle : Arithmetic::kDouble;
}

Resources misc_cost(const BackendConfig& be) {
  Datapath d;
  d.fp(1, backend_arithmetic(be) == Arithmetic::kSingle ? kSingleAdd : kDoubleAdd);
  return d.resources();
}

}  // namespace edx::arch::cost
