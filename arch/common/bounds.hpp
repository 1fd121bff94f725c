#pragma once
// Ranges of keys that several components declare (issue 45): each is what the model can take, so
// that any value inside it gives finite figures on every trace the reader accepts, and a value
// outside it is refused at its file:line naming the key (docs/RELIABILITY.md, "Input limits").
// Simulated time is integer picoseconds below 2^64 (213 days, sim_core/time.hpp); the reader's
// caps bound a frame's work (workloads/trace/validate.cpp), and these bound the time per unit of
// work, so that their product stays far inside it.
#include "common/config_fields.hpp"

namespace edx::arch::bounds {

/// An FPGA unit's clock, 0.001 to 1000 MHz. Fabric clocks of the devices edx models run 100-700
/// MHz (the paper's designs: 150 MHz); 1 kHz is five orders below them, kept for studies that
/// make a unit the bottleneck (the attribution tests run a 10 kHz gemm). Below it a cycle is a
/// millisecond or more and one frame of a capped trace (64 x W x H items at 1/1024 a cycle)
/// passes 2^64 ps; at it, such a frame may still: simulate_system then names the trace and the
/// platform file.
inline Bounds clock_mhz() { return Bounds::at_least(0.001).at_most(1000); }
/// A unit's own clock: 0 (its section's clock) or a clock_mhz() (the key's range is [0, 1000];
/// its section's validate() refuses (0, 1) with this text).
inline constexpr const char* kUnitClockExpected =
    "0 (the section's clock_mhz) or a number in [0.001, 1000]";
inline bool unit_clock_ok(double mhz) { return mhz == 0 || clock_mhz().contains(mhz); }

/// The fewest items (pixels, rows) a streaming datapath moves a cycle: 1/1024, the resolution
/// the stencil-buffer model keeps rates at (memory_plan.cpp: multiples of 1/1024 a cycle).
inline constexpr double kMinPerCycle = 1.0 / 1024;
/// The most: 1024 pixels a cycle (8 kbit of 8-bit pixels), wider than any line of a frame the
/// FE streams a cycle at the resolutions edx traces (up to 1280x720 in the paper).
inline constexpr double kMaxPerCycle = 1024;
/// A streaming rate in pixels a cycle: [1/1024, 1024].
inline Bounds pixels_per_cycle() { return Bounds::at_least(kMinPerCycle).at_most(kMaxPerCycle); }

/// Operations a unit issues a cycle (tests, MACs, words): 1 to 65536, 64x the widest unit a
/// device's DSPs can build (a ZU9's 2520 DSPs, a Virtex-7's 3600, are 1000-odd MACs).
inline Bounds ops_per_cycle() { return Bounds::at_least(1).at_most(65536); }

/// A window's side in pixels (stencils, patches, block-matching windows): 1 to 255, eight times
/// ORB's 31-pixel patch, the widest the pipeline uses; a buffer of the window's lines is sized
/// from it (BRAM words = side x line width). `fewest`: the key's own least side.
inline Bounds window_side(double fewest = 1) { return Bounds::at_least(fewest).at_most(255); }

/// A pipelined operator's latency (divider, square root), 1 to 10000 cycles: 150 times the
/// 57 cycles of the slowest double-precision operator of Xilinx's Floating-Point IP (PG060).
inline Bounds latency_cycles() { return Bounds::at_least(1).at_most(10000); }

/// An energy per operation or per byte, 0 to 10^6 pJ: 10^4 times DRAM's ~100 pJ a byte, so that
/// a frame's energy (at most ~10^13 operations or bytes) stays a finite number of joules.
inline Bounds energy_pj() { return Bounds::at_least(0).at_most(1e6); }

/// A dimensionless calibration factor on energy or power: (0, 1000].
inline Bounds energy_scale() { return Bounds::above(0).at_most(1000); }

}  // namespace edx::arch::bounds
