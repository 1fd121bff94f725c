#pragma once
// A platform description (configs/*.yaml, docs/MODEL.md): the accelerator's configured
// datapath and memories, the links, and the host CPU, as plain structs parsed from YAML.
//
//   name: edx_car
//   description: ...
//   device: xc7v690t
//   host: {kind: suite_scaled, frontend_suite_ms: 71.2, ...,
//          active_w: 15}                        HostProcessor (arch/host; kind optional)
//   frontend: {clock_mhz: 150, ...}             FrontendConfig
//   backend: {kind: fpga_matrix_units, units: {gemm: {block: 4}}, ...}
//                                               OffloadAccelerator (arch/backend)
//   link: {kind: dma, preset: pcie3_x8, ...}    Link (arch/link: a component kind)
//   memory: {kind: bram, allow_bram18: true}    OnChipMemory (arch/memory: a component kind)
//   transfers: {feature_id_bytes: 4, ...}       FrameTransferConfig
//   cost: {...}  power: {...}                   cost::CostConfig, cost::PowerConfig
//   scheduler: {policy: regression, training_fraction: 0.25}
//   system: {sensor_fps: 0, queue_depth: 2, drop: oldest, ...}   SystemConfig (system_config.hpp)
// Every section is optional (defaults); unknown keys and wrong types are file:line:key errors.
// Each struct declares its keys once, in a field list (common/config_fields.hpp), which
// drives parsing, validation, JSON and the reference of every key (docs/CONFIG.md).
//
// `extends: parent.yaml` (path relative to the file) starts from the parent's keys: the
// child's keys override them, recursively by map (a map merges key by key, anything else
// replaces). Chains are allowed; a cycle or a missing parent is an error naming the file and
// line of the `extends:`. Errors in the merged config name the file and line where the key was
// written (PlatformSource keeps, per dotted key, the file it came from).
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "arch/backend/accelerators/fpga_matrix_units.hpp"
#include "arch/backend/offload_accelerator.hpp"
#include "arch/cost/cost_config.hpp"
#include "arch/frontend/frontend_config.hpp"
#include "arch/host/coprocessor.hpp"
#include "arch/host/host_processor.hpp"
#include "arch/link/frame_transfers.hpp"
#include "arch/link/link.hpp"
#include "arch/memory/on_chip_memory.hpp"
#include "arch/platform/ros_transport.hpp"
#include "arch/platform/system_config.hpp"
#include "arch/scheduler/scheduler.hpp"
#include "common/input_error.hpp"

namespace edx::arch {

/// `scheduler:` section: the offload policy of Sec. VI-B (arch/scheduler).
struct SchedulerConfig {
  OffloadPolicy policy = OffloadPolicy::kRegression;
  /// Leading share of each accelerable kernel's invocations its regression model is fitted on
  /// (paper Sec. VII-A: 25 % of the frames); those invocations run on the host.
  double training_fraction = 0.25;
  /// The kernels that may leave the host (arch/kernels descriptors; default the paper's three).
  /// Each invocation runs its ops, recorded in the trace or derived from its sizes, on the
  /// backend units; the policy decides per invocation.
  std::vector<std::string> offload = paper_offload_set();
  /// True when `kernel` is in the offload set.
  bool offloads(const std::string& kernel) const;
  /// Every key of `scheduler:` (docs/CONFIG.md).
  static const FieldList<SchedulerConfig>& fields();
  void validate() const;
  nlohmann::json to_json() const;
};

/// A platform's YAML after `extends:` merging, before parsing: the merged tree (every node keeps
/// the line it was written on) and, per dotted key ("backend.units.gemm.block", "backend"), where
/// it was written: the file (its line is the node's), or a place of its own for a key set in code
/// (a sweep's value: the spec's line).
struct PlatformSource {
  YAML::Node root;
  std::string file;                           ///< the file loaded (the leaf of the chain)
  std::map<std::string, InputPlace> origins;  ///< dotted key -> where it was written
  /// Reads `path` and its `extends:` chain. Errors: file:line of the offending `extends:`.
  static PlatformSource load(const std::filesystem::path& path);
  /// Sets the dotted `key` to `value` (creating maps on the way), written at `origin`.
  void set(const std::string& key, const YAML::Node& value, InputPlace origin);
};

/// The host processor kind of a `host:` section without `kind:`.
inline constexpr const char* kDefaultHostKind = "suite_scaled";

struct Platform {
  std::string name;
  std::string description;
  std::string device = "xc7v690t";  ///< the FPGA (arch/memory/bram.hpp Device::by_name)
  /// The host CPU (`host:`): its times, cores and power; the accelerated system's host.
  std::shared_ptr<const HostProcessor> host =
      ComponentRegistry<HostProcessor>::instance().make(kDefaultHostKind);
  /// The CPU-only baseline's host (`baseline_host:`, a host map of any kind) when it is another
  /// CPU than the accelerated system's (Edx-Drone: the TX1 against the ZU9CG's own cores);
  /// nullptr: the baseline runs on `host`.
  std::shared_ptr<const HostProcessor> baseline_host;
  /// The host of a variant: `host`, or the baseline's own.
  const HostProcessor& host_of(bool accelerated) const {
    return accelerated || !baseline_host ? *host : *baseline_host;
  }
  /// The CPU-only baseline's offload coprocessor (`coprocessor:`, a mobile GPU or DSP,
  /// arch/host/coprocessor.hpp): the rows it states run on it, the rest on the baseline's host;
  /// nullptr: the baseline is the CPU alone. The accelerated system does not use it.
  std::shared_ptr<const Coprocessor> coprocessor;
  FrontendConfig frontend;
  /// Host <-> FPGA (`link:`; default the dma kind's defaults, PCIe 3.0 x8).
  std::shared_ptr<const Link> link = ComponentRegistry<Link>::instance().make(kDefaultLinkKind);
  /// The accelerator's on-chip memory (`memory:`; default the bram kind's defaults).
  std::shared_ptr<const OnChipMemory> memory =
      ComponentRegistry<OnChipMemory>::instance().make(kDefaultMemoryKind);
  FrameTransferConfig transfers;  ///< what crosses the link per frame
  /// The offload accelerator (`backend:`, a registered kind; the paper's FPGA matrix units).
  std::shared_ptr<const OffloadAccelerator> backend = fpga_matrix_units();
  cost::CostConfig cost;    ///< resource model knobs
  cost::PowerConfig power;  ///< energy model constants
  SchedulerConfig scheduler;
  SystemConfig system;  ///< the whole-system DES: camera, queues, contention
  RosTransport ros;     ///< the CPU baseline as ROS 1 nodes (`ros:`; off by default)
  /// The file it was loaded from and where each dotted key was written (load(); empty for a
  /// platform built in code), so that an error found later, while simulating, names them.
  std::string file;
  std::map<std::string, InputPlace> origins;
  /// `error` placed at the file and line of its key (the file that wrote the longest known
  /// prefix of it; a key of no file: the platform's file) when it names no place yet: a product
  /// of in-range values that the model cannot hold, found when a trace meets the platform.
  InputError locate(const InputError& error) const;
  nlohmann::json to_json() const;
  /// Every section's validate() (a platform built or changed in code); load() already did.
  void validate() const;

  /// The top-level keys (name, description, device); each section has its own list.
  static const FieldList<Platform>& fields();
  /// Every key a platform file may hold, section by section, with its default
  /// (`edx config --reference`, docs/CONFIG.md).
  static std::vector<ReferenceRow> reference();

  /// Reads a platform YAML file; errors name the file, line and key (unknown keys included).
  static Platform load(const std::filesystem::path& path);
  /// Parses YAML text; `where` names it in errors.
  static Platform parse(const std::string& text, const std::string& where);
  /// Parses a merged tree; an error is reported against the file that wrote its key.
  static Platform parse(const PlatformSource& source);
};

/// docs/CONFIG.md: a heading and Platform::reference() as Markdown tables.
std::string config_reference_markdown();

}  // namespace edx::arch
