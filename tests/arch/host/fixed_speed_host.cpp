// A host processor kind of the tests' own (issue 40's "adding a kind is one source file plus its
// registration"): a CPU `speed` times as fast as the machine that traced, on every row alike.
//
//   t(row) = t_trace(row) / speed        (the trace's measured CPU times)
#include "arch/host/host_processor.hpp"

namespace edx::arch {
namespace {

class FixedSpeedHost final : public HostProcessor {
 public:
  struct Params {
    double speed = 1.0;  ///< this host's speed over the tracing machine's
    int cores = 2;
    double active_w = 10.0;
    double idle_w = 1.0;
    static const FieldList<Params>& fields() {
      using C = Params;
      static const FieldList<C> list = {
          field("speed", &C::speed, "", "speed over the tracing machine's", Bounds::above(0)),
          field("cores", &C::cores, "", "cores the DES gives the host's threads",
                Bounds::at_least(1)),
          field("active_w", &C::active_w, "W", "package power while computing",
                Bounds::at_least(0)),
          field("idle_w", &C::idle_w, "W", "package power while waiting", Bounds::at_least(0)),
      };
      return list;
    }
    void validate() const { check_fields(*this, "host", fields()); }
  };
  explicit FixedSpeedHost(const Params& params) : params_(params) {}

  std::string_view kind() const override { return "fixed_speed"; }
  nlohmann::json params_json() const override { return params_to_json(params_); }
  std::string display_name() const override { return "fixed-speed host"; }
  int cores() const override { return params_.cores; }
  HostPower power() const override { return {params_.active_w, params_.idle_w}; }

  PlatformHostTimes host_times(const std::vector<trace::FrameTrace>& frames,
                               const trace::TraceMeta& trace_meta, const std::string& trace_name,
                               const HostCostModel* costs) const override {
    // The trace's own times (a host without suite times), each over the speed.
    PlatformHostTimes t = PlatformHostTimes::suite_scaled(SuiteTimes{}, HostTimeSource::kMeasured,
                                                          frames, trace_meta, trace_name, costs);
    const auto over_speed = [this](std::vector<double>& ms) {
      for (double& v : ms) v /= params_.speed;
    };
    over_speed(t.frontend_ms);
    over_speed(t.backend_ms);
    for (std::vector<double>& kernels : t.kernel_ms) over_speed(kernels);
    return t;
  }

 private:
  Params params_;
};

}  // namespace

EDX_REGISTER_COMPONENT(HostProcessor, FixedSpeedHost, "fixed_speed",
                       "a CPU a fixed factor faster than the tracing machine (a test's kind)");

}  // namespace edx::arch
