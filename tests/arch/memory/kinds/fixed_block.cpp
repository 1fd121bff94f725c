// A memory kind added by a test in one file, as a user would add one (issue 40): blocks of a
// fixed number of bytes in any shape, so that a W-bit x D-word structure takes
//   blocks  ceil(W D / (8 bytes_per_block)) a copy (one column of that many rows)
//   LUTs    none (no read multiplexers)
//   energy  pj_per_byte a byte
#include "arch/memory/on_chip_memory.hpp"

namespace edx::arch {
namespace {

class FixedBlock final : public OnChipMemory {
 public:
  struct Params {
    std::int64_t bytes_per_block = 4096;
    double pj_per_byte = 1.0;
    static const FieldList<Params>& fields() {
      using C = Params;
      static const FieldList<C> list = {
          field("bytes_per_block", &C::bytes_per_block, "bytes", "bytes a block holds",
                Bounds::at_least(1).at_most(1 << 30)),
          field("pj_per_byte", &C::pj_per_byte, "pJ/byte", "energy of a byte read or written",
                Bounds::at_least(0)),
      };
      return list;
    }
    void validate() const { check_fields(*this, "memory", fields()); }
  };
  explicit FixedBlock(const Params& params) : params_(params) {}

  std::string_view kind() const override { return "fixed_block"; }
  nlohmann::json params_json() const override { return params_to_json(params_); }
  double pj_per_byte() const override { return params_.pj_per_byte; }

  BramMapping mapping(const MemoryStructure& s) const override {
    s.validate();
    const std::int64_t bits = 8 * params_.bytes_per_block;
    BramMapping m;
    m.aspect = {static_cast<int>(std::min<std::int64_t>(s.width_bits, bits)), 0, false, false};
    m.aspect.depth_words =
        m.aspect.width_bits > 0 ? static_cast<int>(bits / m.aspect.width_bits) : 0;
    m.columns = 1;
    m.rows = (s.width_bits * s.depth_words + bits - 1) / bits;  // ceil(W D / bits)
    m.blocks = static_cast<double>(m.rows);
    return m;
  }

  cost::Resources cost(const MemoryStructure& s) const override {
    cost::Resources r;
    r.bram = mapping(s).blocks * static_cast<double>(s.count);
    return r;
  }

 private:
  Params params_;
};

}  // namespace

EDX_REGISTER_COMPONENT(OnChipMemory, FixedBlock, "fixed_block",
                       "blocks of a fixed byte count in any shape (a test's kind)");

}  // namespace edx::arch
