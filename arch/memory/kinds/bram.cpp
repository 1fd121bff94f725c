// The memory kind `bram` (docs/MODEL.md, "Memories"): Xilinx 36 Kb block RAMs, each structure in
// the aspect ratio with the fewest blocks (arch/memory/bram.hpp map_to_bram: BRAM36, and BRAM18
// halves at 0.5 block when allowed), read through a multiplexer when it is stacked in rows:
//
//   blocks  count x min over aspects (w, d) of ceil(W / w) * ceil(D / d)   (x 0.5 for BRAM18)
//   LUTs    count x W x ceil((r - 1) / 3) for r > 1 block rows: an r:1 mux of the word's width
//           (resources.hpp: a LUT6 is a 4:1 mux, UG474)
//   energy  pj_per_byte a byte read or written: 1.25 pJ, an 8 KB SRAM's 10 pJ per 64-bit
//           access (Horowitz, ISSCC 2014)
//
//   memory: {kind: bram, allow_bram18: false}
#include "arch/common/bounds.hpp"
#include "arch/memory/on_chip_memory.hpp"

namespace edx::arch {
namespace {

class Bram final : public OnChipMemory {
 public:
  struct Params {
    bool allow_bram18 = true;   ///< map small memories to BRAM18 halves (UG473 / UG573)
    bool read_muxes = true;     ///< count the LUT muxes selecting among stacked block rows
    double pj_per_byte = 1.25;  ///< 8 KB SRAM, 10 pJ per 64-bit access (Horowitz 2014)
    static const FieldList<Params>& fields() {
      using C = Params;
      static const FieldList<C> list = {
          field("allow_bram18", &C::allow_bram18, "", "map small memories to BRAM18 halves"),
          field("read_muxes", &C::read_muxes, "",
                "count the LUT muxes selecting among stacked BRAM rows"),
          field("pj_per_byte", &C::pj_per_byte, "pJ/byte",
                "on-chip SRAM access (Horowitz 2014: 8 KB SRAM, 10 pJ per 64 bits)",
                bounds::energy_pj()),
      };
      return list;
    }
    void validate() const { check_fields(*this, "memory", fields()); }
  };
  explicit Bram(const Params& params) : params_(params) {}

  std::string_view kind() const override { return "bram"; }
  nlohmann::json params_json() const override { return params_to_json(params_); }
  double pj_per_byte() const override { return params_.pj_per_byte; }

  BramMapping mapping(const MemoryStructure& s) const override {
    return map_to_bram(s.width_bits, s.depth_words, params_.allow_bram18);
  }

  cost::Resources cost(const MemoryStructure& s) const override {
    const BramMapping m = mapping(s);
    cost::Datapath d;
    d.bram(m.blocks * double(s.count));
    if (params_.read_muxes && m.rows > 1) d.muxes(double(s.count), s.width_bits, m.rows);
    return d.resources();
  }

 private:
  Params params_;
};

}  // namespace

EDX_REGISTER_COMPONENT(OnChipMemory, Bram, "bram",
                       "Xilinx BRAM36 / BRAM18 blocks in their fewest-blocks aspect, stacked rows "
                       "read through LUT muxes (UG473, UG573)");

}  // namespace edx::arch
