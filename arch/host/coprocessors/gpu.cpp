// A mobile GPU beside the host CPU (docs/MODEL.md, "GPU and DSP baselines"; issue 41): the
// frontend's vector image tasks and the backend's dense floating-point kernels it is given, at
// its datasheet rates (whole device, work units a ns as arch/host/throughput.hpp's):
//
//   simd_int   f × int16_ops_per_cycle       (16-bit lane operations of every ALU)
//   fp32       f × fp32_flops_per_cycle      (FMA = 2)
//   fp64       f × fp64_flops_per_cycle, or the fp32 rate when it has no fp64 (a port to it
//              computes the backend in single precision; its accuracy is not modeled)
//   memory     memory_gb_per_s
//
// Scalar-bound rows (gathers, branchy bookkeeping) stay on the CPU.
#include <fmt/format.h>

#include "arch/host/coprocessor.hpp"

namespace edx::arch {
namespace {

class Gpu final : public OffloadDevice {
 public:
  struct Params {
    OffloadKeys offload;
    double clock_ghz = 0.6;
    double int16_ops_per_cycle = 256;
    double fp32_flops_per_cycle = 512;
    double fp64_flops_per_cycle = 0;  ///< 0: no double precision
    double memory_gb_per_s = 25.6;

    static const FieldList<Params>& fields() {
      using C = Params;
      static const FieldList<C> list = joined<C>({
          nested_fields<C>("", &C::offload, OffloadKeys::fields()),
          {
              field("clock_ghz", &C::clock_ghz, "GHz", "sustained shader clock",
                    Bounds::above(0).below(10)),
              field("int16_ops_per_cycle", &C::int16_ops_per_cycle, "",
                    "16-bit integer lane operations a cycle, every ALU", Bounds::above(0)),
              field("fp32_flops_per_cycle", &C::fp32_flops_per_cycle, "",
                    "single-precision flops a cycle, every ALU (FMA = 2)", Bounds::above(0)),
              field("fp64_flops_per_cycle", &C::fp64_flops_per_cycle, "",
                    "double-precision flops a cycle (0: none; fp64 rows run at the fp32 rate, "
                    "in single precision)",
                    Bounds::at_least(0)),
              field("memory_gb_per_s", &C::memory_gb_per_s, "GB/s",
                    "DRAM bandwidth it reaches (shared with the CPU)", Bounds::above(0)),
          },
      });
      return list;
    }
    static bool supports(ThroughputClass c) { return c != ThroughputClass::kScalar; }
    void validate() const {
      check_fields(*this, "coprocessor", fields());
      OffloadDevice::validate_keys(offload, "gpu", &Params::supports);
    }
    static Params parse(YamlFields& yaml) { return parse_coprocessor_params<Params>(yaml, "gpu"); }
    static std::vector<ReferenceRow> reference(const std::string& section,
                                               const std::string& title) {
      return coprocessor_reference(section, title, fields(), Params{});
    }
  };

  explicit Gpu(const Params& params) : OffloadDevice(params.offload), params_(params) {}
  const Params& params() const { return params_; }
  std::string_view kind() const override { return "gpu"; }
  nlohmann::json params_json() const override { return params_to_json(params_); }

  double rate(ThroughputClass c) const override {
    const double f = params_.clock_ghz;
    switch (c) {
      case ThroughputClass::kSimdInteger:
        return f * params_.int16_ops_per_cycle;
      case ThroughputClass::kFloat32:
        return f * params_.fp32_flops_per_cycle;
      case ThroughputClass::kFloat64:
        return f * (params_.fp64_flops_per_cycle > 0 ? params_.fp64_flops_per_cycle
                                                     : params_.fp32_flops_per_cycle);
      case ThroughputClass::kMemory:
        return params_.memory_gb_per_s;
      case ThroughputClass::kScalar:
        break;
    }
    throw std::logic_error("gpu: no scalar rate (validate refuses scalar rows)");
  }

 private:
  Params params_;
};

}  // namespace

EDX_REGISTER_COMPONENT(Coprocessor, Gpu, "gpu",
                       "a mobile GPU by its datasheet: launch, per-frame setup, its rates on "
                       "vector and floating-point work (docs/MODEL.md, GPU and DSP baselines)");

}  // namespace edx::arch
