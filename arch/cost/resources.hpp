#pragma once
// FPGA resources of a datapath (docs/MODEL.md): LUTs, flip-flops, DSP slices and BRAM36 blocks,
// and the primitives a unit is built from, each with its cost on 7-series / UltraScale(+) fabric.
//
// Fabric primitives (assumed model of the CLB, UG474 "7 Series FPGAs CLB User Guide" and UG574
// for UltraScale: a LUT6 per bit of a carry-chain adder or comparator, a LUT6 as a 4:1 mux, a
// LUT6 reducing 6 inputs of an AND/OR tree, two 2-input functions per LUT6 with its dual output;
// DSP48E1/E2 signed 25x18 / 27x18 multipliers with an internal accumulator, UG479 / UG579):
//
//   adder / subtractor of w bits         w LUT,          w FF (registered result)
//   comparator of w bits                 w LUT,          1 FF
//   |a − b| of w bits                    2w LUT,         w FF (subtract, conditional negate)
//   AND/OR reduction of n inputs         ⌈(n−1)/5⌉ LUT,  1 FF
//   bitwise XOR of w bits                ⌈w/2⌉ LUT,      0 FF (dual-output LUT6)
//   k:1 mux of w bits                    w·⌈(k−1)/3⌉ LUT, 0 FF
//   adder tree of n inputs of w bits     Σ_levels ⌊m/2⌋ adders of (w + level) bits, m halving
//   popcount of n bits                   adder tree of n 1-bit inputs
//   integer multiplier a x b bits        ⌈a/25⌉·⌈b/18⌉ DSP (operands and product in the DSP)
//   register of w bits                   w FF
//
// Floating-point operators come from Xilinx's Floating-Point Operator core (PG060); see
// FpOperatorCost below.
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

namespace edx::arch::cost {

/// LUT, FF, DSP and BRAM36 blocks (fractional blocks: BRAM18 halves).
struct Resources {
  double lut = 0, ff = 0, dsp = 0, bram = 0;

  Resources& operator+=(const Resources& o);
  friend Resources operator+(Resources a, const Resources& b) { return a += b; }
  friend Resources operator*(Resources a, double s) {
    a.lut *= s, a.ff *= s, a.dsp *= s, a.bram *= s;
    return a;
  }
  /// The value of resource `index` (0 lut, 1 ff, 2 dsp, 3 bram).
  double operator[](int index) const;
  nlohmann::json to_json() const;
};

/// One unit, memory or overhead entry of a resource report (resource_report.hpp).
struct CostEntry {
  std::string name;      ///< "FD", "gemm", "fe.L0.line_fifo", "control"
  std::string group;     ///< "frontend" or "backend"
  std::string kind;      ///< "unit", "memory" or "control"
  Resources shared;      ///< as built (shared across modes, cameras, kernels)
  double ns_copies = 1;  ///< copies without sharing (control: 1, its ns is computed)
  Resources ns;          ///< the N.S. resources: shared x ns_copies (control: overhead of N.S.)
  /// An entry whose N.S. resources are `shared` x `ns_copies`.
  static CostEntry replicated(std::string name, std::string group, std::string kind,
                              const Resources& shared, double ns_copies);
  nlohmann::json to_json() const;
};

/// Names of the four resources in Resources::operator[] order.
inline constexpr const char* kResourceNames[4] = {"lut", "ff", "dsp", "bram"};

/// One floating-point operator instance of PG060 (Floating-Point Operator v7.1), non-blocking,
/// maximum latency, with the DSP usage named. Source: the resource figures of the core on
/// 7-series as Vivado HLS instantiates it (dadd/dmul/fadd/fmul "full_dsp"/"max_dsp", ddiv/dsqrt/
/// fdiv fabric only); rounded. docs/MODEL.md lists them; treat them as typical, not exact.
struct FpOperatorCost {
  const char* name;
  double lut, ff, dsp;
  Resources resources() const { return {lut, ff, dsp, 0}; }
};

/// Double-precision multiply, "max DSP usage": 11 DSP48E1, 208 LUT, 317 FF (PG060).
inline constexpr FpOperatorCost kDoubleMultiply{"double multiply", 208, 317, 11};
/// Double-precision add/subtract, "full DSP usage": 3 DSP48E1, 1149 LUT, 445 FF (PG060).
inline constexpr FpOperatorCost kDoubleAdd{"double add", 1149, 445, 3};
/// Double-precision divide, fabric only: 0 DSP, ~3200 LUT, ~3200 FF (PG060, approximate).
inline constexpr FpOperatorCost kDoubleDivide{"double divide", 3200, 3200, 0};
/// Double-precision square root, fabric only: 0 DSP, ~2000 LUT, ~1800 FF (PG060, approximate).
inline constexpr FpOperatorCost kDoubleSqrt{"double sqrt", 2000, 1800, 0};
/// Single-precision multiply, "max DSP usage": 3 DSP48E1, 143 LUT, 321 FF (PG060).
inline constexpr FpOperatorCost kSingleMultiply{"single multiply", 143, 321, 3};
/// Single-precision add/subtract, "full DSP usage": 2 DSP48E1, 390 LUT, 205 FF (PG060).
inline constexpr FpOperatorCost kSingleAdd{"single add", 390, 205, 2};
/// Single-precision divide, fabric only: 0 DSP, ~800 LUT, ~1400 FF (PG060, approximate).
inline constexpr FpOperatorCost kSingleDivide{"single divide", 800, 1400, 0};
/// Single-precision square root, fabric only: 0 DSP, ~500 LUT, ~800 FF (PG060, approximate).
inline constexpr FpOperatorCost kSingleSqrt{"single sqrt", 500, 800, 0};

/// Arithmetic of a datapath's multiply-accumulates.
enum class Arithmetic { kFixed, kSingle, kDouble };
/// "fixed", "single", "double"; throws std::runtime_error naming `what` otherwise.
Arithmetic parse_arithmetic(const std::string& text, const std::string& what);
const char* to_string(Arithmetic arithmetic);

/// Bits of one word of a backend datapath of `arithmetic`: 32 single, else 64.
int word_bits(Arithmetic arithmetic);

/// Accumulates the primitives of one unit (the table at the top of this header).
class Datapath {
 public:
  Datapath& adders(double count, int bits);
  Datapath& comparators(double count, int bits);
  Datapath& abs_diffs(double count, int bits);
  Datapath& reductions(double count, int inputs);
  Datapath& xors(double count, int bits);
  Datapath& muxes(double count, std::int64_t bits, std::int64_t ways);
  /// ⌊m/2⌋ adders per level, widths growing by one bit a level; returns the result width.
  int adder_tree(double count, int inputs, int bits);
  Datapath& popcounts(double count, int bits);
  Datapath& multipliers(double count, int a_bits, int b_bits);
  Datapath& registers(double bits);
  Datapath& fp(double count, const FpOperatorCost& op);
  /// `count` multiply-accumulates: fixed point (an a x b DSP multiply accumulating in the DSP),
  /// or a PG060 multiplier + adder of the given precision.
  Datapath& macs(double count, Arithmetic arithmetic, int a_bits = 16, int b_bits = 16);
  Datapath& divider(double count, Arithmetic arithmetic);
  Datapath& sqrt(double count, Arithmetic arithmetic);
  Datapath& bram(double blocks);

  const Resources& resources() const { return r_; }

 private:
  Resources r_;
};

/// A unit's address generator (AGX of Fig. 14): row, column and block counters of 16 bits.
void address_generator(Datapath& datapath);

}  // namespace edx::arch::cost
