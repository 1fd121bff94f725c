#pragma once
// A host processor (docs/MODEL.md, "Host CPU" and "Components"): the CPU a platform's software
// runs on, the baseline's whole pipeline and the accelerated system's work not offloaded. One
// interface, its kinds beside it in arch/host/processors/ (one file each, registered there by
// name), one instance per platform (`host:`, docs/CONFIG.md):
//
//   host: {kind: suite_scaled, name: ..., frontend_suite_ms: 167.88, ..., cores: 4,
//          active_w: 15, idle_w: 2}
//
// `kind` is optional (suite_scaled). A kind owns its parameters, how a trace's recorded work or
// measured CPU times become host times on it, the cores the system DES gives its threads, and its
// package power (the energy model, arch/cost/energy.hpp).
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "arch/common/registry.hpp"
#include "arch/host/host_model.hpp"
#include "common/config_fields.hpp"
#include "workloads/trace/records.hpp"

namespace edx::arch {

/// The host package's power, W (docs/MODEL.md, "Energy"): while any of its cores computes, and
/// while all of them wait (idle_w <= active_w). The package draws active_w at most, however
/// many cores are busy.
struct HostPower {
  double active_w = 0;
  double idle_w = 0;
  /// `active_w`, `idle_w`: the keys of every host kind (nested into its Params).
  static const FieldList<HostPower>& fields();
  /// Throws "host.idle_w: expected a power in [0, active_w] W" (and the fields' own checks).
  void validate() const;
};

/// A host's times on the reference suite and where its host times come from, as the keys every
/// host kind that maps a trace's times through them declares (nested into its Params): `suite`,
/// `frontend_suite_ms`, `provenance`, `backend_suite_ms`, `backend_provenance`, `times`.
struct SuiteTimeKeys {
  int suite = trace::kHostSpeedSuite;
  double frontend_suite_ms = 0;
  std::string provenance;
  double backend_suite_ms = 0;
  std::string backend_provenance;
  HostTimeSource times = HostTimeSource::kModeled;
  static const FieldList<SuiteTimeKeys>& fields();
  /// The suite times of host `name`.
  SuiteTimes suite_times(const std::string& name) const;
};

class HostProcessor : public Component {
 public:
  static constexpr const char* kKindName = "host processor";
  /// The processor as reports name it ("Intel Kaby Lake, 4 cores, 1.6 GHz").
  virtual std::string display_name() const = 0;
  /// A trace's host times on this processor, per frame (its frontend, its backend, each kernel
  /// row), ms. `costs`: the op-count model's cost table (host_costs.hpp; nullptr: the bundled
  /// one). Throws std::runtime_error naming `trace_name` when the trace cannot be mapped onto it.
  virtual PlatformHostTimes host_times(const std::vector<trace::FrameTrace>& frames,
                                       const trace::TraceMeta& trace_meta,
                                       const std::string& trace_name,
                                       const HostCostModel* costs = nullptr) const = 0;
  /// Cores the whole-system DES gives the host's threads (>= 1).
  virtual int cores() const = 0;
  /// Its package power (before power.host_power_scale).
  virtual HostPower power() const = 0;
};

/// The file of bundled description `name` in `dir` (configs/host/processors, ...): DIR/NAME.yaml;
/// throws InputError "expected a bundled <what> (the names, sorted), got 'NAME'" when there is
/// none.
std::string bundled_description_file(const std::string& dir, const std::string& what,
                                     const std::string& name);

/// The host processor of kind `kind` with `params` (YAML text of its keys, e.g.
/// "{cores: 1}") over its defaults: code and tests that build a host without a platform file.
/// Errors name "code" and the key.
std::shared_ptr<const HostProcessor> make_host_processor(std::string_view kind,
                                                         const std::string& params = "{}");

}  // namespace edx::arch
