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
    /// Reference-suite version the times below are for (trace::kHostSpeedSuite when written).
    int suite = trace::kHostSpeedSuite;
    double frontend_suite_ms = 0;  ///< S_fe, CPU ms; 0 with backend_suite_ms 0: identity
    std::string provenance = "identity: the trace host is the target";
    double backend_suite_ms = 0;  ///< S_be, CPU ms
    std::string backend_provenance = "identity: the trace host is the target";
    HostTimeSource times = HostTimeSource::kModeled;
    /// 2, the fewest that run the frontend and backend threads side by side.
    int cores = 2;
    double active_w = 15.0;  ///< assumed: Kaby Lake U TDP (docs/MODEL.md, "Energy")
    double idle_w = 2.0;     ///< assumed

    static const FieldList<Params>& fields() {
      using C = Params;
      const Bounds non_negative = Bounds::at_least(0);
      static const FieldList<C> list = {
          field("name", &C::name, "", "the target host CPU"),
          field("suite", &C::suite, "",
                "reference-suite version the suite times are for (a trace's must match)",
                Bounds::at_least(1)),
          field("frontend_suite_ms", &C::frontend_suite_ms, "ms",
                "the reference suite's frontend part on this host, CPU time (0 with "
                "backend_suite_ms 0: the trace host is the target)",
                non_negative),
          field("provenance", &C::provenance, "", "where frontend_suite_ms comes from"),
          field("backend_suite_ms", &C::backend_suite_ms, "ms",
                "the reference suite's backend part on this host, CPU time", non_negative),
          field("backend_provenance", &C::backend_provenance, "",
                "where backend_suite_ms comes from"),
          enum_field(
              "times", &C::times, {"modeled", "measured"},
              [](HostTimeSource t) { return std::string(to_string(t)); },
              [](const std::string& text) { return parse_host_times(text); },
              "host times from the op-count model of the trace's work (modeled: the same on any "
              "tracing machine) or the trace's measured CPU times (measured); either is mapped "
              "by the suite times"),
          field("cores", &C::cores, "", "cores the DES gives the host's threads",
                Bounds::at_least(1)),
          field("active_w", &C::active_w, "W", "package power while any core computes",
                non_negative),
          field("idle_w", &C::idle_w, "W", "package power while every core waits (<= active_w)",
                non_negative),
      };
      return list;
    }

    /// Throws "host.<key>: expected ..." (both suite times or neither; idle_w <= active_w).
    void validate() const {
      check_fields(*this, "host", fields());
      if ((frontend_suite_ms > 0) != (backend_suite_ms > 0)) {
        require_field(false, "host",
                      frontend_suite_ms > 0 ? "backend_suite_ms" : "frontend_suite_ms",
                      "both suite times or neither (neither: the trace host is the target)");
      }
      require_field(idle_w <= active_w, "host", "idle_w", "a power in [0, active_w] W");
    }
  };

  explicit SuiteScaled(const Params& params) : params_(params) {}

  std::string_view kind() const override { return "suite_scaled"; }
  nlohmann::json params_json() const override { return params_to_json(params_); }
  std::string display_name() const override { return params_.name; }
  int cores() const override { return params_.cores; }
  HostPower power() const override { return {params_.active_w, params_.idle_w}; }

  PlatformHostTimes host_times(const std::vector<trace::FrameTrace>& frames,
                               const trace::TraceMeta& trace_meta, const std::string& trace_name,
                               const HostCostModel* costs) const override {
    const SuiteTimes suite{params_.name,
                           params_.suite,
                           params_.frontend_suite_ms,
                           params_.backend_suite_ms,
                           params_.provenance,
                           params_.backend_provenance};
    return PlatformHostTimes::suite_scaled(suite, params_.times, frames, trace_meta, trace_name,
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
