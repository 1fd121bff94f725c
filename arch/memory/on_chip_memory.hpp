#pragma once
// The accelerator's on-chip memory as a component kind (docs/MODEL.md, "Memories" and
// "Components"): one interface, its implementations beside it in arch/memory/kinds/ (one file
// each, registered there by name), and the platform's one instance of it (`memory:`,
// docs/CONFIG.md):
//
//   memory: {kind: bram, allow_bram18: true, read_muxes: true, pj_per_byte: 1.25}
//
// Every memory a platform sizes (the frontend's stencil buffers, FIFOs and scratchpad, the
// backend's scratchpad) comes in as a MemoryStructure of W bits x D words, `count` copies; the
// kind says how one copy maps onto the device's memory blocks (counted in BRAM36 blocks, the unit
// of the device's budget, Device::bram36_blocks), what all copies cost in fabric resources and
// what a byte read or written costs in energy.
#include <cstdint>
#include <memory>

#include "arch/common/registry.hpp"
#include "arch/cost/resources.hpp"
#include "arch/memory/bram.hpp"

namespace edx::arch {

class OnChipMemory : public Component {
 public:
  static constexpr const char* kKindName = "memory";
  /// How one copy of `structure` maps onto blocks (its `count` ignored). A zero-sized structure
  /// maps to 0 blocks. Throws std::runtime_error for negative sizes.
  virtual BramMapping mapping(const MemoryStructure& structure) const = 0;
  /// The resources of all `count` copies of `structure`: `bram` its blocks (count x
  /// mapping().blocks) and the LUTs, FFs and DSPs around them (e.g. read multiplexers).
  virtual cost::Resources cost(const MemoryStructure& structure) const = 0;
  /// Energy of one byte read or written, pJ (docs/MODEL.md, "Energy per frame": e_bram).
  virtual double pj_per_byte() const = 0;
};

/// The kind a platform without `memory: {kind: ...}` has (arch/memory/kinds/bram.cpp).
inline constexpr const char* kDefaultMemoryKind = "bram";

}  // namespace edx::arch
