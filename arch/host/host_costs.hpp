#pragma once
// The op-count host model (docs/MODEL.md, "Host CPU: modeled times"; issue 17): a row's host
// time from the work the trace records for it, not from the clock of the machine that traced it.
//
//   t(row) = S_part × Σ_j c_kind,j · x_j(row)
//
// x(row) are the row's work regressors (a call, pixels, comparisons, the flops of its matrix
// ops, m·n², ...; one list per task and kernel kind, host_costs.cpp), c the kind's costs in ns
// per unit of work on a host whose reference-suite part (frontend for tasks, backend for
// kernels; docs/TRACE.md "Host speed") takes 1 ms, and S_part the target host's suite time in
// ms (SuiteTimes, host_model.hpp). The costs are fitted once (`edx host-costs fit`) by least
// squares on traces' measured CPU times, each over its frame's local suite time, and committed
// (configs/host/host_costs.yaml): every later trace is costed from its work alone, so the same
// work gives the same host times on any machine under any load.
#include <yaml-cpp/yaml.h>

#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "common/config_fields.hpp"
#include "workloads/trace/records.hpp"

namespace edx::arch {

/// The cost model of one kind of row: its regressors' names and the costs (ns per unit work per
/// suite-ms), with what the fit saw.
struct RowCost {
  std::vector<std::string> features;
  std::vector<double> costs;
  std::size_t samples = 0;    ///< rows fitted
  double r2 = 0;              ///< on the fitted rows
  double measured_share = 0;  ///< the kind's share of its part's fitted time
  /// Σ_j c_j x_j.
  double predict(const std::vector<double>& x) const;
};

/// What a model row is: a frontend task, a backend kernel, or a frame's time outside its rows.
enum class CostPart { kFrontendTask, kBackendKernel, kFrontendRest, kBackendRest };

/// Regressors of a row: kind key (e.g. "FD", "kalman_gain", "backend_rest:vio") and values.
struct WorkRow {
  CostPart part = CostPart::kFrontendTask;
  std::string kind;
  std::vector<double> x;
};

/// Feature names of a kind (the same order as work_of's values).
std::vector<std::string> feature_names(CostPart part, const std::string& kind);
/// `image_pixels`: the frame's level-0 image (image_pixels(frame)).
WorkRow work_of(const trace::TaskRecord& task, double image_pixels);
/// Width × height of the frame's level-0 image (its first task with per-level work), or 0.
double image_pixels(const trace::FrameTrace& frame);
/// Throws std::runtime_error naming the kernel when its detail JSON is malformed.
WorkRow work_of(const trace::KernelRecord& kernel);
WorkRow frontend_rest_of(const trace::FrameTrace& frame);
/// A frame whose backend ran (a mode, or kernels): only those have a backend rest.
bool ran_backend(const trace::FrameTrace& frame);
WorkRow backend_rest_of(const trace::FrameTrace& frame);

/// The fitted costs of every kind (configs/host/host_costs.yaml).
struct HostCostModel {
  int suite = 0;                            ///< reference-suite version the costs are relative to
  std::string provenance;                   ///< traces, revision, date, machine of the fit
  std::map<std::string, RowCost> frontend;  ///< tasks and "frontend_rest"
  std::map<std::string, RowCost> backend;   ///< kernels and "backend_rest:<mode>"
  std::string source;  ///< the file it was read from ("": fitted in this process)

  /// Modeled time of a row in ns per suite-ms of its part. Throws std::runtime_error naming
  /// the table's file (its source), the kind and `where` (the trace and frame that needs it)
  /// when the table has no costs for it.
  double predict(const WorkRow& row, const std::string& where) const;
  /// As predict, std::nullopt when the table has no costs for the row's kind.
  std::optional<double> try_predict(const WorkRow& row) const;

  YAML::Emitter& emit(YAML::Emitter& out) const;
  std::string to_yaml() const;
  /// Errors name `where` (the file), the line and the key; a kind whose feature names differ
  /// from this edx's is an error (re-fit).
  static HostCostModel from_yaml(const YAML::Node& root, const std::string& where);
  static HostCostModel load(const std::string& path);
  /// The table's keys, for the reference (docs/CONFIG.md, "Other input files").
  static std::vector<ReferenceRow> reference();
  /// The bundled table, configs/host/host_costs.yaml (common::find_resource), read once.
  static const HostCostModel& bundled();
};

struct KernelFeature;  // a kernel kind's regressor (host_costs.cpp)
struct TaskFeature;    // a task kind's regressor

/// Σ_j c_j x_j of tasks' and kernels' rows: costs.try_predict(work_of(...)) to the bit, with the
/// per-kind look-ups (regressor list, costs) done once per kind and no row built, as
/// suite_scaled needs for every task and kernel of every frame. Errors as work_of's. One
/// thread's; `costs` must outlive it.
class RowCoster {
 public:
  explicit RowCoster(const HostCostModel& costs) : costs_(costs) {}
  /// costs.try_predict(work_of(kernel)).
  std::optional<double> kernel(const trace::KernelRecord& kernel);
  /// costs.try_predict(work_of(task, image_pixels)).
  std::optional<double> task(const trace::TaskRecord& task, double image_pixels);

 private:
  struct KernelKind {
    const std::vector<KernelFeature>* features = nullptr;
    bool uses_detail = false;
    const RowCost* cost = nullptr;  ///< nullptr: the table has none
  };
  struct TaskKind {
    const std::vector<TaskFeature>* features = nullptr;
    const RowCost* cost = nullptr;
  };
  const HostCostModel& costs_;
  std::unordered_map<std::string, KernelKind> kernels_;
  std::map<trace::Task, TaskKind> tasks_;
  /// Kernels' details parsed, by their text (a trace repeats them: the car mix's 1 847 details
  /// are 695 texts); only objects are kept, a bad one throws every time.
  std::unordered_map<std::string, nlohmann::json> details_;
  std::vector<double> x_;  ///< the row's regressors (reused)
};

/// One trace's rows for the fit: its frames and the local suite speed of each.
struct CostFitInput {
  std::string name;
  const std::vector<trace::FrameTrace>* frames = nullptr;
  const trace::TraceMeta* meta = nullptr;
};

/// Least squares of each kind's measured CPU time over its frame's local suite time (ms) on its
/// regressors; a regressor whose cost comes out negative is dropped and the kind refitted, so
/// every cost is ≥ 0. Kinds with fewer rows than 3 × regressors keep only the per-call cost.
/// Throws when a trace has no frames or no host_speed.
HostCostModel fit_host_costs(const std::vector<CostFitInput>& traces,
                             const std::string& provenance);

/// One line per kind of `model` fitted from fewer rows than 3 × its regressors (so only its
/// per-call cost was fitted), for `edx host-costs fit` to warn about.
std::vector<std::string> fit_warnings(const HostCostModel& model);

/// `base` with the costs of `kinds` replaced by those of `fitted` (a partial re-fit: a kernel
/// whose work changed is re-fitted on new traces, the other kinds keep their costs; the costs
/// are per suite-ms, so traces of another day or machine fit the same table). Throws
/// std::runtime_error when the suites differ or `fitted` has no costs for a kind.
HostCostModel replace_kinds(HostCostModel base, const HostCostModel& fitted,
                            const std::vector<std::string>& kinds);

/// Per kind over a trace: rows, measured and modeled ns per suite-ms summed, and R² per row;
/// `edx host-costs check` prints it.
nlohmann::json compare_host_costs(const HostCostModel& model, const CostFitInput& trace);

}  // namespace edx::arch
