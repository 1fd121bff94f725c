// Matching optimization, MO (paper Sec. V-B): the stereo matches' initial correspondences by the
// Hamming distance of 256-bit rBRIEF descriptors, on `comparators` distance units. docs/MODEL.md:
//
//   cycles     ⌈comparisons / comparators⌉ (one distance a unit a cycle)
//   resources  per unit a 256-bit XOR and its popcount tree, best and second-best tracking
//   activity   a 256-bit XOR and a popcount (255 adds) a comparison; two 32 B descriptors read
#include <cmath>

#include "arch/frontend/frontend_config.hpp"
#include "arch/frontend/task_timing.hpp"

namespace edx::arch {
namespace {

constexpr int kDescriptorBits = 256;  // rBRIEF

class Hamming final : public FrontendUnit {
 public:
  struct Params {
    int comparators = 4;  ///< 256-bit Hamming-distance units (assumed)
    static const FieldList<Params>& fields() {
      using C = Params;
      static const FieldList<C> list = {
          field("comparators", &C::comparators, "", "256-bit Hamming-distance units",
                Bounds::at_least(1)),
      };
      return list;
    }
    void validate() const { check_fields(*this, "hamming", fields()); }
  };
  explicit Hamming(const Params& params) : params_(params) {}

  std::string_view kind() const override { return "hamming"; }
  nlohmann::json params_json() const override { return params_to_json(params_); }
  trace::Task task() const override { return trace::Task::MO; }
  double stream_pixels_per_cycle(const FrontendConfig&) const override { return 0.0; }

  std::int64_t cycles(const trace::TaskRecord& row, std::int64_t,
                      const FrontendConfig&) const override {
    return (row.comparisons + params_.comparators - 1) / params_.comparators;
  }

  cost::Resources resources(const FrontendConfig&) const override {
    const int units = params_.comparators;
    const int distance_bits = static_cast<int>(std::log2(kDescriptorBits)) + 1;
    cost::Datapath d;
    d.xors(units, kDescriptorBits);
    d.popcounts(units, kDescriptorBits);
    d.comparators(2.0 * units, distance_bits);  // best and second best
    d.registers(2.0 * kDescriptorBits + 4.0 * units * (distance_bits + 16));
    return d.resources();
  }

  cost::FrameActivity activity(const trace::TaskRecord& row, const FrontendConfig&) const override {
    cost::FrameActivity a;
    a.int8_ops = 511 * double(row.comparisons);
    a.bram_bytes = 64 * double(row.comparisons);
    return a;
  }

 private:
  Params params_;
};

}  // namespace

EDX_REGISTER_COMPONENT(FrontendUnit, Hamming, "hamming",
                       "Hamming distances of 256-bit descriptors: MO (Sec. V-B)");

}  // namespace edx::arch
