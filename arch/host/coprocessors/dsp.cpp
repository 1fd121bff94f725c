// A DSP with wide integer vectors beside the host CPU (docs/MODEL.md, "GPU and DSP baselines";
// issue 41), as the Hexagon's HVX: fixed-point vector units only, so it runs the frontend's
// integer image tasks it is given and no floating-point work. Its rates (whole device, work units
// a ns as arch/host/throughput.hpp's):
//
//   simd_int   f × vector_units × (vector_bits / 16) × vector_ops_per_cycle   (16-bit lanes)
//   memory     memory_gb_per_s
//
// Scalar and floating-point rows stay on the CPU.
#include <fmt/format.h>

#include "arch/host/coprocessor.hpp"

namespace edx::arch {
namespace {

class Dsp final : public OffloadDevice {
 public:
  struct Params {
    OffloadKeys offload;
    double clock_ghz = 0.5;
    int vector_units = 2;
    int vector_bits = 1024;
    double vector_ops_per_cycle = 1;
    double memory_gb_per_s = 29.8;

    static const FieldList<Params>& fields() {
      using C = Params;
      static const FieldList<C> list = joined<C>({
          nested_fields<C>("", &C::offload, OffloadKeys::fields()),
          {
              field("clock_ghz", &C::clock_ghz, "GHz", "sustained clock of the vector units",
                    Bounds::above(0).below(10)),
              field("vector_units", &C::vector_units, "",
                    "vector contexts computing at once (each its own vector unit)",
                    Bounds::at_least(1).at_most(64)),
              field("vector_bits", &C::vector_bits, "bits", "vector register width",
                    Bounds::at_least(16).at_most(8192)),
              field("vector_ops_per_cycle", &C::vector_ops_per_cycle, "",
                    "vector instructions a unit sustains a cycle on the image kernels",
                    Bounds::above(0).at_most(16)),
              field("memory_gb_per_s", &C::memory_gb_per_s, "GB/s",
                    "DRAM bandwidth it reaches (shared with the CPU)", Bounds::above(0)),
          },
      });
      return list;
    }
    static bool supports(ThroughputClass c) {
      return c == ThroughputClass::kSimdInteger || c == ThroughputClass::kMemory;
    }
    void validate() const {
      check_fields(*this, "coprocessor", fields());
      OffloadDevice::validate_keys(offload, "dsp", &Params::supports);
    }
    static Params parse(YamlFields& yaml) { return parse_coprocessor_params<Params>(yaml, "dsp"); }
    static std::vector<ReferenceRow> reference(const std::string& section,
                                               const std::string& title) {
      return coprocessor_reference(section, title, fields(), Params{});
    }
  };

  explicit Dsp(const Params& params) : OffloadDevice(params.offload), params_(params) {}
  const Params& params() const { return params_; }
  std::string_view kind() const override { return "dsp"; }
  nlohmann::json params_json() const override { return params_to_json(params_); }

  double rate(ThroughputClass c) const override {
    switch (c) {
      case ThroughputClass::kSimdInteger:
        return params_.clock_ghz * params_.vector_units * (params_.vector_bits / 16.0) *
               params_.vector_ops_per_cycle;
      case ThroughputClass::kMemory:
        return params_.memory_gb_per_s;
      default:
        break;
    }
    throw std::logic_error(
        fmt::format("dsp: no {} rate (validate refuses such rows)", to_string(c)));
  }

 private:
  Params params_;
};

}  // namespace

EDX_REGISTER_COMPONENT(Coprocessor, Dsp, "dsp",
                       "a DSP with integer vector units by its datasheet: call overhead, its "
                       "rate on integer image work (docs/MODEL.md, GPU and DSP baselines)");

}  // namespace edx::arch
