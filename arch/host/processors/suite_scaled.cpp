// A CPU given by its times on the reference suite (docs/MODEL.md, "Host CPU"; DESIGN.md, "Host
// CPU"): one factor for frontend work and one for backend work, whatever the kernel.
//
//   modeled:   t(row) = S_part × Σ_j c_kind,j · x_j(row)         (host_costs.hpp)
//   measured:  t_platform(f) = t_trace(f) × S_part / S_trace(f)   (host_model.hpp)
//   S_fe = frontend_suite_ms, S_be = backend_suite_ms; both 0: the trace host is the target
//   (the trace's times as they are)
//
// The DES runs the host's threads on `cores` cores; the package draws active_w while any core
// computes and idle_w while all wait (docs/MODEL.md, "Energy").
#include "arch/host/host_processor.hpp"

namespace edx::arch {
namespace {

class SuiteScaled final : public HostProcessor {
 public:
  struct Params {
    std::string name = "trace host";
    /// S_fe and S_be, CPU ms (both 0: identity, the trace host is the target), `times`.
    SuiteTimeKeys suite{.provenance = "identity: the trace host is the target",
                        .backend_provenance = "identity: the trace host is the target"};
    /// 2, the fewest that run the frontend and backend threads side by side.
    int cores = 2;
    /// Assumed: Kaby Lake U TDP, and idle (docs/MODEL.md, "Energy").
    HostPower power{15.0, 2.0};

    static const FieldList<Params>& fields() {
      using C = Params;
      static const FieldList<C> list = joined<C>({
          {field("name", &C::name, "", "the target host CPU")},
          nested_fields<C>("", &C::suite, SuiteTimeKeys::fields()),
          {field("cores", &C::cores, "", "cores the DES gives the host's threads",
                 Bounds::at_least(1))},
          nested_fields<C>("", &C::power, HostPower::fields()),
      });
      return list;
    }

    /// Throws "host.<key>: expected ..." (both suite times or neither; idle_w <= active_w).
    void validate() const {
      check_fields(*this, "host", fields());
      if ((suite.frontend_suite_ms > 0) != (suite.backend_suite_ms > 0)) {
        require_field(false, "host",
                      suite.frontend_suite_ms > 0 ? "backend_suite_ms" : "frontend_suite_ms",
                      "both suite times or neither (neither: the trace host is the target)");
      }
      power.validate();
    }
  };

  explicit SuiteScaled(const Params& params) : params_(params) {}

  std::string_view kind() const override { return "suite_scaled"; }
  nlohmann::json params_json() const override { return params_to_json(params_); }
  std::string display_name() const override { return params_.name; }
  int cores() const override { return params_.cores; }
  HostPower power() const override { return params_.power; }

  PlatformHostTimes host_times(const std::vector<trace::FrameTrace>& frames,
                               const trace::TraceMeta& trace_meta, const std::string& trace_name,
                               const HostCostModel* costs) const override {
    return PlatformHostTimes::suite_scaled(params_.suite.suite_times(params_.name),
                                           params_.suite.times, frames, trace_meta, trace_name,
                                           costs);
  }

 private:
  Params params_;
};

}  // namespace

EDX_REGISTER_COMPONENT(HostProcessor, SuiteScaled, "suite_scaled",
                       "a CPU by its times on the reference suite: the op-count model's or the "
                       "trace's measured host times scaled by them (docs/MODEL.md, Host CPU)");

}  // namespace edx::arch
