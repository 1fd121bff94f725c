#pragma once
// A frontend unit (paper Sec. V, Fig. 11): the hardware that runs one task of the frontend's task
// graph (FD, IF, FC, MO, DR, DC, LSS; Sec. V-B). One interface, its implementations beside it in
// arch/frontend/units/ (one file each, registered there by name), and the platform's instances:
// `frontend.units.<task>` (docs/CONFIG.md). A unit kind owns its parameters (its datapath's
// parallelism: lanes, comparators, tests a cycle, arithmetic), the cycles of a task row of the
// trace, its LUT/FF/DSP/BRAM and the work a row does for the energy model; the frontend
// (FrontendConfig) holds the instances and what they share: the clock, the FE input stream's rate,
// the stencil sizes (the algorithm's, which the trace's rows override), the memories' formats.
//
//   frontend:
//     fe_pixels_per_cycle: 2
//     units:
//       FC: {kind: rbrief, tests_per_cycle: 32}
//       DR: {kind: sad_disparity, pixels_per_cycle: 0.25, sad_units: 11}
//
// The task graph is the paper's, so the instances are named by the task they serve, and every
// task has one; `count` copies of a unit are a pool the frontend DES grants first come, first
// served (two FD copies let the left and right images run side by side instead of time-sharing
// one FE engine).
#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "arch/common/registry.hpp"
#include "arch/cost/energy_activity.hpp"
#include "arch/cost/resources.hpp"
#include "common/config_fields.hpp"
#include "workloads/trace/records.hpp"

namespace edx::arch {

struct FrontendConfig;

class FrontendUnit : public Component {
 public:
  static constexpr const char* kKindName = "frontend unit";
  /// The task of the graph it runs.
  virtual trace::Task task() const = 0;
  /// Cycles of one task row (the trace's work counts) on one copy; `level0_pixels` is the
  /// image's size (W H), `frontend` what the units share.
  virtual std::int64_t cycles(const trace::TaskRecord& row, std::int64_t level0_pixels,
                              const FrontendConfig& frontend) const = 0;
  /// Pixels a cycle it streams its input image at, for the memory plan's buffer timing; 0 for a
  /// unit that reads no image stream (MO, LSS).
  virtual double stream_pixels_per_cycle(const FrontendConfig& frontend) const = 0;
  /// LUT, FF, DSP and BRAM of one copy.
  virtual cost::Resources resources(const FrontendConfig& frontend) const = 0;
  /// The work one task row does, as the energy model counts it (pixel operations, MACs of its
  /// arithmetic, on-chip bytes; docs/MODEL.md "Energy").
  virtual cost::FrameActivity activity(const trace::TaskRecord& row,
                                       const FrontendConfig& frontend) const = 0;
};

/// One instance of a unit kind in a platform: `frontend.units.<task>`.
struct FrontendUnitInstance {
  std::string name;                          ///< the task it serves ("FD")
  std::shared_ptr<const FrontendUnit> unit;  ///< the kind, with its parameters
  int count = 1;                             ///< copies (a pool in the frontend DES)
  double clock_mhz = 0;                      ///< its clock; 0: the frontend's (frontend.clock_mhz)

  /// The keys every instance has besides `kind` and its kind's own (docs/CONFIG.md).
  static const FieldList<FrontendUnitInstance>& fields();
  nlohmann::json to_json() const;  ///< kind, instance keys and the kind's parameters
};

/// The instance of `task` of kind `kind` with its parameters at their defaults, or `params` (YAML
/// of the kind's keys, e.g. "{tests_per_cycle: 16}") over them.
FrontendUnitInstance make_frontend_unit(trace::Task task, std::string_view kind,
                                        const std::string& params = "{}", int count = 1);

}  // namespace edx::arch
