#pragma once
// Parameterised resource cost of each hardware unit (docs/MODEL.md, "Units"), built from the
// primitives of arch/cost/resources.hpp and the unit's configured dimensions: the seven frontend
// tasks (paper Sec. V, FrontendConfig), and the backend's glue ("Misc." of Fig. 14). Each backend
// matrix unit kind costs itself (arch/backend/units/). Memories are not here: they come in as
// BRAM structures (arch/cost/resource_report.hpp).
#include "arch/backend/backend_config.hpp"
#include "arch/cost/cost_config.hpp"
#include "arch/cost/resources.hpp"
#include "arch/frontend/frontend_config.hpp"

namespace edx::arch::cost {

/// Pixel lanes of a stream rate: ⌈pixels per cycle⌉ (a fractional rate reuses one lane).
int lanes_of(double pixels_per_cycle);

// Frontend (8-bit pixels).
/// FAST segment test on ⌈p⌉ lanes: per lane, c±t adders, 16 circle pixels x (brighter,
/// darker) 8-bit comparisons, 2 x 16 nine-input ANDs (a contiguous arc at every start), the
/// score (16 |p − c| and their adder tree), 3x3 NMS (8 score comparators); the fd x (fd + lanes
/// − 1) window shift register.
Resources fd_cost(const FrontendConfig& fe);
/// k x k Gaussian (k = if_stencil) on ⌈p⌉ lanes: k² MACs per lane (2k when separable) and the
/// adder tree of the products; the window shift register.
Resources if_cost(const FrontendConfig& fe, const CostConfig& cost);
/// rBRIEF: orientation by intensity moments over fc_patch_rows_per_cycle patch rows a cycle
/// (per row: x·I products and their tree, the row sum tree, one y·rowsum product, two
/// accumulators; a 16-stage CORDIC atan2), fc_tests_per_cycle tests a cycle (two patch²:1 pixel
/// muxes and a comparator each) from the patch² window register, the rotated-pattern table in
/// BRAM (fc_angle_bins x 256 pairs).
Resources fc_cost(const FrontendConfig& fe, const CostConfig& cost);
/// mo_comparators 256-bit Hamming units (XOR + popcount tree) with best / second-best tracking.
Resources mo_cost(const FrontendConfig& fe);
/// dr_sad_units SAD units, each one dr_window row of |L − R| a cycle with its adder tree and
/// accumulator; the argmin over the units, sub-pixel refinement, the window shift registers.
Resources dr_cost(const FrontendConfig& fe);
/// Scharr (dc_stencil) gradients x and y and pyrDown's pyramid_filter Gaussian, constant
/// coefficients as shift-adds, on ⌈dc_pixels_per_cycle⌉ lanes; the window shift register.
Resources dc_cost(const FrontendConfig& fe);
/// lss_macs_per_cycle MACs (16 x 16 bits, or frontend_arithmetic), five accumulators, the 2x2
/// solve of a Gauss-Newton step (4 multiplies, 2 adds, 1 divide in single precision).
Resources lss_cost(const FrontendConfig& fe, const CostConfig& cost);

/// "Misc." of Fig. 14: one adder (e.g. + R in S = H P H^T + R).
Resources misc_cost(const BackendConfig& be);
/// The backend units' MACs: single precision for backend.scalar_bytes 4, double for 8.
Arithmetic backend_arithmetic(const BackendConfig& be);

}  // namespace edx::arch::cost
