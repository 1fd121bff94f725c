#pragma once
// Mapping on-chip memory structures onto Xilinx 36 Kb block RAMs (the memory kind `bram`,
// arch/memory/kinds/bram.cpp), and checking a design's structures, mapped by the platform's
// memory kind, against a device (docs/MODEL.md, "Memories").
//
// A BRAM36 holds 36 Kb = 36864 bits = 4608 bytes including the parity bits (32 Kb = 4096 bytes
// of data). It can be configured with these aspect ratios (width x depth), identical on 7-series
// (UG473, ch. 1, port aspect ratios) and UltraScale(+) (UG573, ch. 1, port aspect ratios):
//   32K x 1, 16K x 2, 8K x 4, 4K x 9, 2K x 18, 1K x 36 (true dual port) and 512 x 72 (simple
//   dual port only).
// Each BRAM36 splits into two independent BRAM18 halves: 16K x 1, 8K x 2, 4K x 4, 2K x 9,
// 1K x 18 and 512 x 36 (simple dual port).
// A structure of W bits x D words in aspect (w, d) needs ceil(W / w) * ceil(D / d) blocks
// (columns side by side for the width, rows stacked for the depth); we pick the aspect with the
// fewest blocks, counting a BRAM18 as 0.5 block.
//
// "MB" convention: everything here reports bytes; MiB means 2^20 bytes. bytes_of_blocks() gives
// either the 4608 bytes with parity or the 4096 data bytes per block (the paper's Sec. VII-B
// resource table "5.0 MB = 87.5 %" of the XC7V690T matches 1470 x 4096 B = 5.74 MiB: 5.0 / 5.74 =
// 87 %).
#include <array>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace edx::arch {

class OnChipMemory;

/// One BRAM configuration: `width_bits` x `depth_words`.
struct BramAspect {
  int width_bits = 0;
  int depth_words = 0;
  bool simple_dual_port_only = false;  ///< 512 x 72 (BRAM36) / 512 x 36 (BRAM18)
  bool half = false;                   ///< a BRAM18 (0.5 block)
};

/// BRAM36 aspect ratios (UG473 and UG573, ch. 1, port aspect ratios).
inline constexpr std::array<BramAspect, 7> kBram36Aspects = {{{1, 32768, false, false},
                                                              {2, 16384, false, false},
                                                              {4, 8192, false, false},
                                                              {9, 4096, false, false},
                                                              {18, 2048, false, false},
                                                              {36, 1024, false, false},
                                                              {72, 512, true, false}}};
/// BRAM18 aspect ratios (UG473 and UG573, ch. 1), 0.5 block each.
inline constexpr std::array<BramAspect, 6> kBram18Aspects = {{{1, 16384, false, true},
                                                              {2, 8192, false, true},
                                                              {4, 4096, false, true},
                                                              {9, 2048, false, true},
                                                              {18, 1024, false, true},
                                                              {36, 512, true, true}}};

/// Bits in one BRAM36 including parity: 36 Kb (UG473 / UG573).
inline constexpr std::int64_t kBram36Bits = 36 * 1024;
/// Bytes in one BRAM36 including parity bits: 36864 / 8 = 4608.
inline constexpr std::int64_t kBram36BytesWithParity = kBram36Bits / 8;
/// Data bytes in one BRAM36 without parity bits: 32 Kb / 8 = 4096.
inline constexpr std::int64_t kBram36DataBytes = 32 * 1024 / 8;

/// Bytes held by `blocks` BRAM36: blocks x 4608 (with parity) or blocks x 4096 (data only).
double bytes_of_blocks(double blocks, bool include_parity);
/// bytes / 2^20.
double to_mib(double bytes);

/// A memory structure: `width_bits` x `depth_words`, instantiated `count` times.
struct MemoryStructure {
  std::string name;
  std::int64_t width_bits = 0;
  std::int64_t depth_words = 0;
  std::int64_t count = 1;
  /// Throws std::runtime_error naming the structure and the bad field.
  void validate() const;
  nlohmann::json to_json() const;
};

/// How one instance of a structure maps onto memory blocks (OnChipMemory::mapping; BRAM36
/// blocks, the unit of the device's budget).
struct BramMapping {
  BramAspect aspect;         ///< the chosen configuration
  std::int64_t columns = 0;  ///< ceil(width_bits / aspect.width_bits)
  std::int64_t rows = 0;     ///< ceil(depth_words / aspect.depth_words)
  double blocks = 0.0;       ///< columns x rows, x 0.5 for a BRAM18 aspect
  nlohmann::json to_json() const;
};

/// The fewest-blocks mapping of one `width_bits` x `depth_words` memory: min over the aspects
/// (w, d) of ceil(W / w) * ceil(D / d) (x 0.5 for BRAM18 when `allow_bram18`). Ties go to the
/// earlier aspect, BRAM36 before BRAM18. A zero-sized memory maps to 0 blocks. Throws
/// std::runtime_error for negative sizes.
BramMapping map_to_bram(std::int64_t width_bits, std::int64_t depth_words,
                        bool allow_bram18 = true);

/// An FPGA device's totals.
struct Device {
  std::string name;
  std::int64_t bram36_blocks = 0;
  std::int64_t luts = 0;
  std::int64_t flip_flops = 0;
  std::int64_t dsps = 0;
  std::string source;  ///< datasheet the numbers come from

  /// Virtex-7 XC7V690T (DS180, "Virtex-7 FPGA Feature Summary"): 108,300 slices x 4
  /// LUTs = 433,200 LUTs; 866,400 CLB flip-flops; 3,600 DSP48E1; 1,470 BRAM36 (52,920 Kb).
  static Device xc7v690t();
  /// Zynq UltraScale+ ZU9CG / ZU9EG (same programmable logic; DS891, "Zynq UltraScale+ MPSoC
  /// Device Feature Summary"): 274,080 CLB LUTs; 548,160 CLB flip-flops; 2,520 DSP48E2; 912
  /// BRAM36 (32.1 Mb).
  static Device zu9eg();
  /// "xc7v690t" or "zu9eg" / "zu9cg" (case-insensitive); std::nullopt otherwise.
  static std::optional<Device> find(const std::string& name);
  /// The names find() knows, for errors: "xc7v690t, zu9eg or zu9cg".
  static const char* known_names();
  /// find(), throwing std::runtime_error for an unknown name.
  static Device by_name(const std::string& name);
  nlohmann::json to_json() const;
};

/// One structure's share of the BRAM budget.
struct StructureUsage {
  MemoryStructure structure;
  BramMapping mapping;  ///< of one instance
  double blocks = 0.0;  ///< of all its copies: the memory kind's cost().bram
};

/// The BRAM use of a named list of structures on a device.
struct BramBudget {
  std::string list_name;
  std::string device_name;
  std::vector<StructureUsage> structures;
  double total_blocks = 0.0;       ///< sum of the structures' blocks
  std::int64_t device_blocks = 0;  ///< the device's BRAM36 count
  double utilization = 0.0;        ///< total_blocks / device_blocks
  bool fits = true;                ///< total_blocks <= device_blocks
  std::string message;             ///< why it does not fit ("" when it fits)

  /// Total bytes, with (4608 B/block) or without (4096 B/block) parity.
  double total_bytes(bool include_parity) const;
  nlohmann::json to_json() const;
};

/// Maps every structure with `memory` (its mapping of one copy; its blocks of all copies),
/// totals them and checks the total against `device`. When it does not fit, `message` names the
/// list, the device and both block counts.
BramBudget check_bram(const std::string& list_name, const std::vector<MemoryStructure>& structures,
                      const Device& device, const OnChipMemory& memory);

}  // namespace edx::arch
