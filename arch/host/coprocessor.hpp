#pragma once
// An offload coprocessor of a CPU baseline (docs/MODEL.md, "GPU and DSP baselines"; issue 41): a
// mobile GPU or DSP beside the host CPU, running the frontend tasks and backend kernels it states
// while the CPU runs the rest. One interface, its kinds beside it in arch/host/coprocessors/ (one
// file each, registered there by name), at most one instance per platform (`coprocessor:`,
// docs/CONFIG.md), used by the CPU baseline only:
//
//   coprocessor: {kind: gpu, device: adreno_530}
//
// A row (a task or kernel of a frame) it runs takes, on it,
//
//   t_dev(row) = launch + t_ref(row) × rate_ref(class) / (rate_dev(class) × e(part))
//
// t_ref the row's time on the reference CPU (the calibrated anchor, arch/host/throughput.hpp),
// class the row kind's bound, rate_dev the device's datasheet rate on the class (the kind's
// formula), e = 1 for the frontend's dense image work and e = sparse_efficiency for the
// backend's small sparse matrices. A frame the device runs anything of first pays
// frame_setup_ms on it (no batching across frames). The device runs one row at a time; the CPU
// thread that hands a row over waits for it without holding a core.
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "arch/common/registry.hpp"
#include "arch/host/host_costs.hpp"
#include "arch/host/host_model.hpp"
#include "arch/host/host_processor.hpp"
#include "arch/host/throughput.hpp"
#include "common/config_fields.hpp"
#include "common/input_error.hpp"
#include "common/yaml_fields.hpp"
#include "workloads/trace/records.hpp"

namespace edx::arch {

/// What a coprocessor runs and what handing it work costs: the keys every coprocessor kind
/// declares (nested into its Params).
struct OffloadKeys {
  std::string name = "coprocessor";  ///< as reports name it
  std::string datasheet;             ///< the documents its figures come from
  /// The anchor CPU (configs/host/processors/) its rows' times are scaled from.
  std::string reference = "kaby_lake_4c";
  std::vector<std::string> tasks;    ///< frontend tasks it runs ("FD", ...)
  std::vector<std::string> kernels;  ///< backend kernels it runs ("kalman_gain", ...)
  double launch_us = 0;              ///< per row it runs: the call's overhead
  std::string launch_provenance;
  double frame_setup_ms = 0;  ///< once per frame it runs anything of
  std::string frame_setup_provenance;
  double sparse_efficiency = 1;  ///< e on the backend's kernels
  std::string sparse_efficiency_provenance = "1: the datasheet peaks' ratio as it is";
  /// A bundled coprocessor whose sparse_efficiency this one takes ("" none).
  std::string sparse_efficiency_of;

  static const FieldList<OffloadKeys>& fields();
};

class Coprocessor : public Component {
 public:
  static constexpr const char* kKindName = "coprocessor";
  /// The device as reports name it ("Qualcomm Adreno 530").
  virtual std::string display_name() const = 0;
  /// Whether it runs rows of this kind (a frontend task or backend kernel it states).
  virtual bool runs(CostPart part, std::string_view kind) const = 0;
  /// A trace's rows in PlatformHostTimes' layout, ms: a row it runs at t_ref × rate ratio / e
  /// (without the launch), every other row and the rests at the reference CPU's time. Throws
  /// std::runtime_error naming `trace_name` as HostProcessor::host_times does.
  virtual PlatformHostTimes device_times(const std::vector<trace::FrameTrace>& frames,
                                         const trace::TraceMeta& trace_meta,
                                         const std::string& trace_name) const = 0;
  /// Per row it runs, ms.
  virtual double launch_ms() const = 0;
  /// Once per frame it runs anything of, ms. (Its energy is not modeled: a baseline with a
  /// coprocessor counts its host package's, docs/MODEL.md "GPU and DSP baselines".)
  virtual double frame_setup_ms() const = 0;
};

/// The coprocessor of kind `kind` with `params` (YAML text of its keys) over its defaults:
/// code and tests that build one without a platform file. Errors name "code" and the key.
std::shared_ptr<const Coprocessor> make_coprocessor(std::string_view kind,
                                                    const std::string& params = "{}");

/// The shared part of the coprocessor kinds: their keys, a bundled description's loading
/// (`device: NAME`, configs/host/coprocessors/NAME.yaml) and the scaling of the reference CPU's
/// row times by a kind's rates.
class OffloadDevice : public Coprocessor {
 public:
  std::string display_name() const override { return keys_.name; }
  bool runs(CostPart part, std::string_view kind) const override;
  PlatformHostTimes device_times(const std::vector<trace::FrameTrace>& frames,
                                 const trace::TraceMeta& trace_meta,
                                 const std::string& trace_name) const override;
  double launch_ms() const override { return keys_.launch_us * 1e-3; }
  double frame_setup_ms() const override { return keys_.frame_setup_ms; }

  /// Its rate on class `c`, work units a ns (throughput.hpp's units, the whole device).
  virtual double rate(ThroughputClass c) const = 0;

  /// Checks `keys` for a kind that runs the classes `supports` accepts: every listed row has a
  /// declared bound of such a class, the reference is a bundled anchor. Throws InputError naming
  /// "coprocessor" and the key.
  static void validate_keys(const OffloadKeys& keys, std::string_view kind,
                            const std::function<bool(ThroughputClass)>& supports);
  /// Resolves `sparse_efficiency_of` (its bundled description's sparse_efficiency and
  /// provenance into `keys`); errors at `yaml`'s key.
  static void share_sparse_efficiency(const YamlFields& yaml, OffloadKeys& keys);
  /// configs/host/coprocessors/NAME.yaml; throws InputError "expected a bundled coprocessor
  /// (the names), got ...".
  static std::string bundled_file(const std::string& name);

 protected:
  explicit OffloadDevice(OffloadKeys keys) : keys_(std::move(keys)) {}
  const OffloadKeys& keys() const { return keys_; }

 private:
  OffloadKeys keys_;
};

/// The YAML map of bundled coprocessor `name` (errors name its file), its `kind` checked to be
/// `kind` and taken.
YamlFields bundled_coprocessor_yaml(const std::string& name, const std::string& kind);

/// A coprocessor kind's reference rows under `section`: `device`, then its keys.
template <class Params>
std::vector<ReferenceRow> coprocessor_reference(const std::string& section,
                                                const std::string& title,
                                                const FieldList<Params>& fields,
                                                const Params& defaults) {
  std::vector<ReferenceRow> rows = {reference_row(
      section, "device", FieldKind::kText, "", std::string(), {}, {},
      "start from a bundled description, configs/host/coprocessors/NAME.yaml (of this kind; the "
      "keys below override its values)")};
  rows.back().group = title;
  for (ReferenceRow& row : reference_rows(section, fields, defaults, title)) {
    rows.push_back(std::move(row));
  }
  return rows;
}

/// Parses a coprocessor kind's Params from `yaml`: `device: NAME` first (the bundled
/// description's keys the defaults; its `kind` must be this one), then the keys here, then the
/// shared sparse efficiency. `Params` nests OffloadKeys as member `offload` and has fields().
template <class Params>
Params parse_coprocessor_params(YamlFields& yaml, const std::string& kind) {
  Params p;
  if (const YAML::Node device = yaml.take("device")) {
    const FieldValue name = read_field_value(yaml, "device", device, FieldKind::kText, {}, {});
    try {
      OffloadDevice::bundled_file(std::get<std::string>(name));
    } catch (const InputError& e) {
      yaml.fail(e.with_key("device"));
    }
    YamlFields bundled = bundled_coprocessor_yaml(std::get<std::string>(name), kind);
    parse_fields(bundled, p, Params::fields());
    bundled.finish();
    OffloadDevice::share_sparse_efficiency(bundled, p.offload);
  }
  const bool own_share = static_cast<bool>(yaml.take("sparse_efficiency_of"));
  if (yaml.take("sparse_efficiency") && !own_share) {
    p.offload.sparse_efficiency_of.clear();
    p.offload.sparse_efficiency_provenance = "set in the platform file";  // unless it says more
  }
  parse_fields(yaml, p, Params::fields());
  if (own_share) OffloadDevice::share_sparse_efficiency(yaml, p.offload);
  return p;
}

}  // namespace edx::arch
