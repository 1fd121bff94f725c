#include "arch/host/host_costs.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <mutex>
#include <stdexcept>

#include "arch/host/host_model.hpp"
#include "common/config_fields.hpp"
#include "common/resources.hpp"
#include "common/yaml_fields.hpp"

namespace edx::arch {

/// A regressor of a kernel row; `uses_detail` when it reads the kernel's detail JSON (which is
/// parsed only for kinds that have such a regressor).
struct KernelFeature {
  const char* name;
  double (*value)(const trace::KernelRecord&, const nlohmann::json& detail);
  bool uses_detail = false;
};
struct TaskFeature {
  const char* name;
  double (*value)(const trace::TaskRecord&, double image_pixels);
};

namespace {

using trace::KernelRecord;
using trace::Op;
using trace::OpRecord;
using trace::TaskRecord;

double d(std::int64_t v) { return static_cast<double>(v); }

/// Flops of a matrix op (LAPACK Working Note 41 counts, leading terms): gemm 2mnk, syrk m²k,
/// potrf/ldlt m³/3, trsm m²n, trsv m², a general inverse (LU + inversion) 2m³, a symmetric one
/// (Cholesky + inversion) m³, transpose none, Householder QR of m x n 2mn² - 2n³/3; of one
/// instance of a batch.
double instance_flops(const OpRecord& op) {
  const double m = d(op.m), n = d(op.n), k = d(op.k);
  switch (op.op) {
    case Op::Gemm:
      return 2 * m * n * k;
    case Op::Syrk:
      return m * m * k;
    case Op::Potrf:
    case Op::Ldlt:
      return m * m * m / 3;
    case Op::Trsm:
      return m * m * n;
    case Op::Trsv:
      return m * m;
    case Op::Transpose:
      return 0;
    case Op::Inverse:
      if (op.flags & trace::op_flags::kDiagonal) return m;  // reciprocals
      return (op.flags & trace::op_flags::kSymmetric) ? m * m * m : 2 * m * m * m;
    case Op::Qr:
      return 2 * m * n * n - 2 * n * n * n / 3;
  }
  return 0;
}

/// Elements one instance of an op reads and writes (operands and result).
double instance_elements(const OpRecord& op) {
  const double m = d(op.m), n = d(op.n), k = d(op.k);
  switch (op.op) {
    case Op::Gemm:
      return m * k + k * n + m * n;
    case Op::Syrk:
      return m * k + m * m;
    case Op::Potrf:
    case Op::Ldlt:
    case Op::Inverse:
      return 2 * m * m;
    case Op::Trsm:
      return m * m + 2 * m * n;
    case Op::Trsv:
      return m * m + 2 * m;
    case Op::Transpose:
    case Op::Qr:
      return 2 * m * n;
  }
  return 0;
}

/// Flops and elements of an op record: its batch of instances.
double op_flops(const OpRecord& op) { return d(op.batch) * instance_flops(op); }
double op_elements(const OpRecord& op) { return d(op.batch) * instance_elements(op); }

double detail_count(const nlohmann::json& detail, const char* key) {
  const auto it = detail.find(key);
  return it != detail.end() && it->is_number() ? it->get<double>() : 0.0;
}

// Kernel regressors: a call, and the sizes its algorithm's cost grows with (docs/TRACE.md for
// m, n, k per kernel; docs/MODEL.md "Host CPU: modeled times" for the table).
#define EDX_KERNEL_FEATURE(name, expr, detail)                              \
  KernelFeature {                                                           \
    name,                                                                   \
        [](const KernelRecord& r, const nlohmann::json& j) -> double {      \
          [[maybe_unused]] const double m = d(r.m), n = d(r.n), k = d(r.k); \
          (void)j;                                                          \
          return (expr);                                                    \
        },                                                                  \
        detail                                                              \
  }
#define EDX_K(name, expr) EDX_KERNEL_FEATURE(name, expr, false)
/// A regressor that reads the detail JSON `j`.
#define EDX_KD(name, expr) EDX_KERNEL_FEATURE(name, expr, true)

const KernelFeature kCall = EDX_K("call", 1.0);

/// Flops of a kernel's recorded ops: its inverses (the host's dense inverse or
/// eigen-decomposition, slower per flop than products) and the rest.
double inverse_flops(const KernelRecord& r) {
  double s = 0;
  for (const OpRecord& op : r.ops) s += op.op == Op::Inverse ? op_flops(op) : 0.0;
  return s;
}
double other_flops(const KernelRecord& r) {
  double s = 0;
  for (const OpRecord& op : r.ops) s += op.op == Op::Inverse ? 0.0 : op_flops(op);
  return s;
}
double sum_elements(const KernelRecord& r) {
  double s = 0;
  for (const OpRecord& op : r.ops) s += op_elements(op);
  return s;
}

const std::map<std::string, std::vector<KernelFeature>>& kernel_table() {
  static const std::map<std::string, std::vector<KernelFeature>> table = {
      // Accelerable kernels: their recorded matrix ops.
      {"projection", {kCall, EDX_K("map_points", m), EDX_K("visible", n)}},
      {"kalman_gain",
       {kCall, EDX_K("inverse_flops", inverse_flops(r)), EDX_K("other_flops", other_flops(r)),
        EDX_K("op_elements", sum_elements(r))}},
      {"marginalization",
       {kCall, EDX_K("inverse_flops", inverse_flops(r)), EDX_K("other_flops", other_flops(r)),
        EDX_K("op_elements", sum_elements(r))}},
      // VIO (docs/VIO.md): m, n, k as docs/TRACE.md lists them.
      {"initialization", {kCall, EDX_K("m", m)}},
      {"imu_propagation", {kCall, EDX_K("m", m), EDX_K("n2", n * n)}},
      // Φ and Q per interval (m), Φ P_IR (n), the symmetrization (n²).
      {"covariance_propagation", {kCall, EDX_K("m", m), EDX_K("n", n), EDX_K("n2", n * n)}},
      {"cloning", {kCall, EDX_K("n2", n * n)}},
      {"jacobians",
       {kCall, EDX_K("mn", m * n), EDX_K("k", k),
        EDX_KD("whitening_flops", detail_count(j, "whitening_flops"))}},
      {"nullspace_projection", {kCall, EDX_K("mn", m * n), EDX_K("kn2", k * n * n)}},
      {"compression", {kCall, EDX_K("mn", m * n), EDX_K("mn2", m * n * n)}},
      {"covariance_update", {kCall, EDX_K("n2", n * n), EDX_K("mn2", m * n * n)}},
      {"clone_marginalization", {kCall, EDX_K("n2", n * n)}},
      {"gps_fusion", {kCall, EDX_K("n2", n * n), EDX_K("mn2", m * n * n)}},
      {"triangulation", {kCall, EDX_K("m", m), EDX_K("n", n)}},
      // m observations aligned, n first windows cut, Gauss-Newton updates (docs/VIO.md).
      {"track_check",
       {kCall, EDX_K("m", m), EDX_K("n", n), EDX_KD("iterations", detail_count(j, "iterations"))}},
      // SLAM (docs/SLAM.md).
      {"tracking", {kCall, EDX_K("m", m)}},
      {"keyframe_selection", {kCall, EDX_K("m", m)}},
      {"preintegration", {kCall, EDX_K("m", m)}},
      {"linearization", {kCall, EDX_K("m", m), EDX_K("n", n), EDX_K("n2", n * n)}},
      // m terms, k of them across keyframes (6x6 blocks), n camera columns (H_cc zeroed).
      {"normal_equations", {kCall, EDX_K("m", m), EDX_K("k", k), EDX_K("n2", n * n)}},
      {"schur_complement", {kCall, EDX_K("m", m), EDX_K("mn", m * n), EDX_K("n2", n * n)}},
      {"solve", {kCall, EDX_K("m2", m * m), EDX_K("m3", m * m * m)}},
      {"lm_iteration", {kCall, EDX_K("m", m), EDX_K("mn", m * n), EDX_K("n3", n * n * n)}},
      {"outlier_rejection", {kCall}},
      // Registration (docs/REGISTRATION.md).
      {"bow_query", {kCall, EDX_KD("postings", detail_count(j, "postings"))}},
      {"matching", {kCall, EDX_KD("comparisons", detail_count(j, "comparisons"))}},
      {"pnp", {kCall, EDX_K("m", m)}},
      {"local_map", {kCall, EDX_K("m", m), EDX_K("k", k)}},
      {"projection_matching",
       {kCall, EDX_K("m", m), EDX_KD("comparisons", detail_count(j, "comparisons"))}},
      {"pose_refinement",
       {kCall, EDX_KD("m_iterations", m * std::max(1.0, detail_count(j, "iterations")))}},
  };
  return table;
}

/// A kernel this edx does not know (e.g. a newer trace's): its call and sizes.
const std::vector<KernelFeature>& generic_kernel() {
  static const std::vector<KernelFeature> features = {kCall, EDX_K("m", m), EDX_K("n", n),
                                                      EDX_K("k", k)};
  return features;
}
#undef EDX_K
#undef EDX_KD
#undef EDX_KERNEL_FEATURE

const std::vector<KernelFeature>& kernel_features(const std::string& kernel) {
  const auto& table = kernel_table();
  const auto it = table.find(kernel);
  return it == table.end() ? generic_kernel() : it->second;
}

#define EDX_T(name, expr)                                                                          \
  TaskFeature {                                                                                    \
    name,                                                                                          \
        []([[maybe_unused]] const TaskRecord& t, [[maybe_unused]] double image_pixels) -> double { \
          return (expr);                                                                           \
        }                                                                                          \
  }

/// LK point solves summed over pyramid levels (each sets up its window's gradient matrix).
double level_points(const TaskRecord& t) {
  double sum = 0;
  for (const trace::LevelWork& level : t.per_level) sum += d(level.points);
  return t.per_level.empty() ? d(t.points) : sum;
}

const std::vector<TaskFeature>& task_features(trace::Task task) {
  using trace::Task;
  const TaskFeature call = EDX_T("call", 1.0);
  static const std::map<Task, std::vector<TaskFeature>> table = {
      {Task::FD,
       {call, EDX_T("pixels", d(t.pixels)), EDX_T("candidates", d(t.candidates)),
        EDX_T("keypoints", d(t.keypoints))}},
      {Task::IF, {call, EDX_T("pixels", d(t.pixels))}},
      {Task::FC, {call, EDX_T("pixels", d(t.pixels)), EDX_T("descriptors", d(t.descriptors))}},
      {Task::MO,
       {call, EDX_T("comparisons", d(t.comparisons)), EDX_T("keypoints", d(t.keypoints))}},
      // DR and LSS read windows scattered over whole images: beside their arithmetic, a cost
      // per call that grows with the image (measured: the same windows cost 35 % more at
      // 1280x720 than at 640x480).
      {Task::DR,
       {call,
        EDX_T("sad_pixels", d(t.windows) * d(t.window_size) * d(t.window_size) * d(t.search_range)),
        EDX_T("image_pixels", image_pixels)}},
      {Task::DC, {call, EDX_T("pixels", d(t.pixels)), EDX_T("points", d(t.points))}},
      {Task::LSS,
       {call, EDX_T("level_point_pixels", level_points(t) * d(t.window_size) * d(t.window_size)),
        EDX_T("iteration_pixels", d(t.iterations) * d(t.window_size) * d(t.window_size)),
        EDX_T("image_pixels", image_pixels)}},
  };
  return table.at(task);
}
#undef EDX_T

// A frame's time outside its rows: a constant and, for the backend, a cost per feature the
// frontend hands over (bookkeeping of tracks).
const std::vector<std::string> kFrontendRestFeatures = {"frame"};
const std::vector<std::string> kBackendRestFeatures = {"frame", "features"};

/// Features the frontend hands to the backend: the left image's described keypoints (tracks
/// and new ones).
double frame_features(const trace::FrameTrace& frame) {
  for (const TaskRecord& t : frame.tasks) {
    if (t.task == trace::Task::FC && t.image == trace::Image::Left) return d(t.descriptors);
  }
  return 0;
}

std::string backend_rest_kind(trace::BackendMode mode) {
  return fmt::format("backend_rest:{}", trace::to_string(mode));
}

/// Least squares with costs ≥ 0 (host_costs.hpp, fit_host_costs).
RowCost fit_kind(const std::vector<std::string>& names, const std::vector<std::vector<double>>& x,
                 const std::vector<double>& y) {
  RowCost cost;
  cost.features = names;
  cost.costs.assign(names.size(), 0.0);
  cost.samples = y.size();
  const std::size_t n = y.size();
  if (n == 0) return cost;
  std::vector<std::size_t> active;
  if (n >= 3 * names.size()) {
    for (std::size_t j = 0; j < names.size(); ++j) active.push_back(j);
  } else {
    active.push_back(0);  // the per-call cost alone
  }
  Eigen::VectorXd b(static_cast<Eigen::Index>(n));
  for (std::size_t i = 0; i < n; ++i) b(static_cast<Eigen::Index>(i)) = y[i];
  Eigen::VectorXd solution;
  while (!active.empty()) {
    Eigen::MatrixXd a(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(active.size()));
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t c = 0; c < active.size(); ++c) {
        a(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(c)) = x[i][active[c]];
      }
    }
    // Columns scaled to unit norm (regressors span 1 to 1e9), solved by pivoted QR (a constant
    // regressor beside the call is rank deficient and gets 0).
    Eigen::VectorXd norms = a.colwise().norm().transpose();
    for (Eigen::Index c = 0; c < norms.size(); ++c) {
      if (norms(c) == 0) norms(c) = 1;
    }
    const Eigen::MatrixXd scaled = a * norms.cwiseInverse().asDiagonal();
    solution = scaled.colPivHouseholderQr().solve(b).cwiseQuotient(norms);
    Eigen::Index worst = 0;
    if (solution.minCoeff(&worst) >= 0) break;
    active.erase(active.begin() + worst);
    solution.resize(0);
  }
  for (std::size_t c = 0; c < active.size(); ++c) {
    cost.costs[active[c]] = solution(static_cast<Eigen::Index>(c));
  }
  double mean = 0;
  for (double v : y) mean += v;
  mean /= static_cast<double>(n);
  double ss_res = 0, ss_tot = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double r = y[i] - cost.predict(x[i]);
    ss_res += r * r;
    ss_tot += (y[i] - mean) * (y[i] - mean);
  }
  cost.r2 = ss_tot > 0 ? 1 - ss_res / ss_tot : 1.0;
  return cost;
}

/// Every row of a trace with its measured time over the local suite time (ns per suite-ms).
struct MeasuredRow {
  WorkRow row;
  double y = 0;
};

std::vector<MeasuredRow> measured_rows(const CostFitInput& input) {
  SuiteTimes unit;  // suite times of 1 ms: the mapping's factors are 1 / S_trace(f) in ms
  unit.suite = trace::host_speed_of(*input.meta, input.name).suite;
  unit.frontend_ms = unit.backend_ms = 1;
  const HostMapping mapping = map_host(unit, *input.meta, input.name);
  std::vector<MeasuredRow> rows;
  for (const trace::FrameTrace& frame : *input.frames) {
    const double fe = mapping.frontend_scale(frame.frame.frame_id);
    const double be = mapping.backend_scale(frame.frame.frame_id);
    double tasks_ns = 0, kernels_ns = 0;
    const double pixels = image_pixels(frame);
    for (const TaskRecord& t : frame.tasks) {
      rows.push_back({work_of(t, pixels), d(t.host_ns) * fe});
      tasks_ns += d(t.host_ns);
    }
    for (const KernelRecord& k : frame.kernels) {
      rows.push_back({work_of(k), d(k.host_ns) * be});
      kernels_ns += d(k.host_ns);
    }
    if (!frame.tasks.empty()) {
      rows.push_back({frontend_rest_of(frame), (d(frame.frame.frontend_host_ns) - tasks_ns) * fe});
    }
    if (ran_backend(frame)) {
      rows.push_back({backend_rest_of(frame), (d(frame.frame.backend_host_ns) - kernels_ns) * be});
    }
  }
  return rows;
}

bool is_frontend(CostPart part) {
  return part == CostPart::kFrontendTask || part == CostPart::kFrontendRest;
}

}  // namespace

double RowCost::predict(const std::vector<double>& x) const {
  double t = 0;
  for (std::size_t j = 0; j < costs.size() && j < x.size(); ++j) t += costs[j] * x[j];
  return t;
}

std::vector<std::string> feature_names(CostPart part, const std::string& kind) {
  std::vector<std::string> names;
  switch (part) {
    case CostPart::kFrontendTask:
      for (const TaskFeature& f : task_features(trace::parse_task(kind))) names.push_back(f.name);
      break;
    case CostPart::kBackendKernel:
      for (const KernelFeature& f : kernel_features(kind)) names.push_back(f.name);
      break;
    case CostPart::kFrontendRest:
      names = kFrontendRestFeatures;
      break;
    case CostPart::kBackendRest:
      names = kBackendRestFeatures;
      break;
  }
  return names;
}

double image_pixels(const trace::FrameTrace& frame) {
  for (const TaskRecord& task : frame.tasks) {
    if (!task.per_level.empty()) {
      return d(task.per_level.front().width) * d(task.per_level.front().height);
    }
  }
  return 0;
}

WorkRow work_of(const TaskRecord& task, double image_pixels) {
  WorkRow row{CostPart::kFrontendTask, trace::to_string(task.task), {}};
  for (const TaskFeature& f : task_features(task.task)) {
    row.x.push_back(f.value(task, image_pixels));
  }
  return row;
}

namespace {

bool any_uses_detail(const std::vector<KernelFeature>& features) {
  return std::any_of(features.begin(), features.end(),
                     [](const KernelFeature& f) { return f.uses_detail; });
}

/// A kernel's detail JSON when its kind reads it, else an empty object; throws when it is not a
/// JSON object.
nlohmann::json kernel_detail(const KernelRecord& kernel, bool uses_detail) {
  nlohmann::json detail = !uses_detail || kernel.detail_json == "{}"
                              ? nlohmann::json::object()
                              : nlohmann::json::parse(kernel.detail_json, nullptr, false);
  if (detail.is_discarded() || !detail.is_object()) {
    throw std::runtime_error(fmt::format("kernel '{}': detail is not a JSON object: {}",
                                         kernel.kernel, kernel.detail_json));
  }
  return detail;
}

}  // namespace

WorkRow work_of(const KernelRecord& kernel) {
  // The detail is parsed only for a kind with a regressor in it (this runs per kernel per
  // frame; the trace reader checked that every detail is a JSON object).
  const std::vector<KernelFeature>& features = kernel_features(kernel.kernel);
  const nlohmann::json detail = kernel_detail(kernel, any_uses_detail(features));
  WorkRow row{CostPart::kBackendKernel, kernel.kernel, {}};
  for (const KernelFeature& f : features) {
    row.x.push_back(f.value(kernel, detail));
  }
  return row;
}

std::optional<double> RowCoster::kernel(const KernelRecord& kernel) {
  auto it = kernels_.find(kernel.kernel);
  if (it == kernels_.end()) {
    KernelKind kind;
    kind.features = &kernel_features(kernel.kernel);
    kind.uses_detail = any_uses_detail(*kind.features);
    const auto cost = costs_.backend.find(kernel.kernel);  // try_predict's look-up
    kind.cost = cost == costs_.backend.end() ? nullptr : &cost->second;
    it = kernels_.emplace(kernel.kernel, kind).first;
  }
  const KernelKind& kind = it->second;
  // work_of's values in its order (all of them: one may throw), then try_predict's sum; the
  // detail as kernel_detail makes it, parsed once per text.
  static const nlohmann::json kNoDetail = nlohmann::json::object();
  const nlohmann::json* detail = &kNoDetail;
  if (kind.uses_detail && kernel.detail_json != "{}") {
    auto found = details_.find(kernel.detail_json);
    if (found == details_.end()) {
      found = details_.emplace(kernel.detail_json, kernel_detail(kernel, true)).first;
    }
    detail = &found->second;
  }
  x_.clear();
  for (const KernelFeature& f : *kind.features) x_.push_back(f.value(kernel, *detail));
  if (kind.cost == nullptr) return std::nullopt;
  return kind.cost->predict(x_);
}

std::optional<double> RowCoster::task(const TaskRecord& task, double image_pixels) {
  auto it = tasks_.find(task.task);
  if (it == tasks_.end()) {
    TaskKind kind;
    kind.features = &task_features(task.task);
    const auto cost = costs_.frontend.find(trace::to_string(task.task));
    kind.cost = cost == costs_.frontend.end() ? nullptr : &cost->second;
    it = tasks_.emplace(task.task, kind).first;
  }
  const TaskKind& kind = it->second;
  x_.clear();
  for (const TaskFeature& f : *kind.features) x_.push_back(f.value(task, image_pixels));
  if (kind.cost == nullptr) return std::nullopt;
  return kind.cost->predict(x_);
}

WorkRow frontend_rest_of(const trace::FrameTrace&) {
  return {CostPart::kFrontendRest, "frontend_rest", {1.0}};
}

bool ran_backend(const trace::FrameTrace& frame) {
  return frame.frame.mode != trace::BackendMode::None || !frame.kernels.empty();
}

WorkRow backend_rest_of(const trace::FrameTrace& frame) {
  return {
      CostPart::kBackendRest, backend_rest_kind(frame.frame.mode), {1.0, frame_features(frame)}};
}

std::optional<double> HostCostModel::try_predict(const WorkRow& row) const {
  const auto& table = is_frontend(row.part) ? frontend : backend;
  const auto it = table.find(row.kind);
  if (it == table.end()) return std::nullopt;
  return it->second.predict(row.x);
}

double HostCostModel::predict(const WorkRow& row, const std::string& where) const {
  if (const std::optional<double> t = try_predict(row)) return *t;
  // The table is at fault, so its file leads; a table fitted in memory has none.
  const std::string kind =
      fmt::format("'{}' ({} kind)", row.kind, is_frontend(row.part) ? "a frontend" : "a backend");
  if (source.empty()) {
    throw std::runtime_error(
        fmt::format("{}: the host cost table (suite v{}) has no costs for {} (re-fit it: edx "
                    "host-costs fit, docs/MODEL.md \"Host CPU\")",
                    where, suite, kind));
  }
  throw std::runtime_error(
      fmt::format("{}: the host cost table (suite v{}) has no costs for {}, which {} needs (re-fit "
                  "it: edx host-costs fit, docs/MODEL.md \"Host CPU\")",
                  source, suite, kind, where));
}

YAML::Emitter& HostCostModel::emit(YAML::Emitter& out) const {
  out.SetDoublePrecision(10);
  out << YAML::BeginMap;
  out << YAML::Key << "suite" << YAML::Value << suite;
  out << YAML::Key << "provenance" << YAML::Value << YAML::DoubleQuoted << provenance;
  const auto section = [&](const char* key, const std::map<std::string, RowCost>& table) {
    out << YAML::Key << key << YAML::Value << YAML::BeginMap;
    for (const auto& [kind, cost] : table) {
      out << YAML::Key << kind << YAML::Value << YAML::Flow << YAML::BeginMap;
      out << YAML::Key << "features" << YAML::Value << YAML::Flow << cost.features;
      out << YAML::Key << "costs" << YAML::Value << YAML::Flow << cost.costs;
      out << YAML::Key << "samples" << YAML::Value << cost.samples;
      out << YAML::Key << "r2" << YAML::Value << cost.r2;
      out << YAML::Key << "share" << YAML::Value << cost.measured_share;
      out << YAML::EndMap;
    }
    out << YAML::EndMap;
  };
  section("frontend", frontend);
  section("backend", backend);
  out << YAML::EndMap;
  return out;
}

std::string HostCostModel::to_yaml() const {
  YAML::Emitter out;
  emit(out);
  return std::string(out.c_str()) + "\n";
}

namespace {

/// The keys of the table's top level (frontend and backend are maps of kinds, read_costs).
const FieldList<HostCostModel>& table_fields() {
  using C = HostCostModel;
  static const FieldList<C> list = {
      field("suite", &C::suite, "", "the reference-suite version the costs are relative to",
            Bounds::at_least(1))
          .expects("the reference-suite version (an integer >= 1)")
          .required(),
      field("provenance", &C::provenance, "", "traces, revision, date and machine of the fit"),
  };
  return list;
}

/// The keys of one kind's costs.
const FieldList<RowCost>& row_cost_fields() {
  using C = RowCost;
  static const FieldList<C> list = {
      field("features", &C::features, "", "the kind's regressors, as this edx names them")
          .required(),
      field("costs", &C::costs, "ns per unit per suite-ms", "one per feature", Bounds::at_least(0))
          .required(),
      field("samples", &C::samples, "", "rows fitted", Bounds::at_least(0)),
      field("r2", &C::r2, "", "R² on the fitted rows"),
      field("share", &C::measured_share, "", "the kind's share of its part's fitted time"),
  };
  return list;
}

/// `key:` (frontend or backend), a map of kinds to their costs, into `table`; a kind's features
/// must be the ones this edx computes (task_part for tasks, kernels; rest_part for "*_rest*").
void read_costs(YamlFields& top, const std::string& key, CostPart task_part, CostPart rest_part,
                std::map<std::string, RowCost>& table) {
  const YAML::Node node = top.take(key);
  if (!node || !node.IsMap()) top.fail(key, "expected a map of kinds");
  for (const auto& entry : node) {
    const std::string kind = entry.first.as<std::string>();
    YamlFields fields(entry.second, top.where(), key + "." + kind);
    RowCost cost;
    parse_fields(fields, cost, row_cost_fields());
    fields.finish();
    std::vector<std::string> expected;
    try {
      expected =
          feature_names(kind.find("_rest") != std::string::npos ? rest_part : task_part, kind);
    } catch (const std::invalid_argument&) {
      fields.fail("", "not a frontend task (FD|IF|FC|MO|DR|DC|LSS) or frontend_rest");
    }
    if (cost.features != expected) {
      fields.fail("", fmt::format("features [{}], but this edx models [{}] (re-fit: edx "
                                  "host-costs fit)",
                                  fmt::join(cost.features, ", "), fmt::join(expected, ", ")));
    }
    if (cost.costs.size() != cost.features.size()) fields.fail("", "expected one cost per feature");
    table[kind] = std::move(cost);
  }
}

}  // namespace

HostCostModel HostCostModel::from_yaml(const YAML::Node& root, const std::string& where) {
  HostCostModel model;
  YamlFields top(root, where, "");
  parse_fields(top, model, table_fields());
  read_costs(top, "frontend", CostPart::kFrontendTask, CostPart::kFrontendRest, model.frontend);
  read_costs(top, "backend", CostPart::kBackendKernel, CostPart::kBackendRest, model.backend);
  top.finish();
  model.source = where;
  return model;
}

std::vector<ReferenceRow> HostCostModel::reference() {
  const std::string file = "Host cost table (`configs/host/host_costs.yaml`, `edx host-costs fit`)";
  std::vector<ReferenceRow> rows = reference_rows("", table_fields(), {}, file + ": top level");
  for (ReferenceRow& row : reference_rows("frontend.<kind>", row_cost_fields(), {},
                                          file + ": `frontend:` and `backend:` kinds")) {
    rows.push_back(std::move(row));
  }
  return rows;
}

HostCostModel HostCostModel::load(const std::string& path) {
  return from_yaml(load_yaml_map(read_input_file(path, "host cost table"), path, "host costs"),
                   path);
}

const HostCostModel& HostCostModel::bundled() {
  static std::once_flag once;
  static HostCostModel model;
  std::call_once(
      once, [] { model = load(common::find_resource("configs/host/host_costs.yaml").string()); });
  return model;
}

HostCostModel fit_host_costs(const std::vector<CostFitInput>& traces,
                             const std::string& provenance) {
  struct Samples {
    CostPart part;
    std::vector<std::vector<double>> x;
    std::vector<double> y;
  };
  std::map<std::string, Samples> kinds;
  HostCostModel model;
  model.suite = 0;
  for (const CostFitInput& input : traces) {
    if (input.frames->empty()) {
      throw std::runtime_error(fmt::format("{}: the trace has no frames to fit", input.name));
    }
    const int suite = trace::host_speed_of(*input.meta, input.name).suite;
    if (model.suite != 0 && suite != model.suite) {
      throw std::runtime_error(
          fmt::format("{}: suite v{}, the other traces' v{}", input.name, suite, model.suite));
    }
    model.suite = suite;
    for (MeasuredRow& r : measured_rows(input)) {
      Samples& s = kinds.try_emplace(r.row.kind, Samples{r.row.part, {}, {}}).first->second;
      s.x.push_back(std::move(r.row.x));
      s.y.push_back(r.y);
    }
  }
  model.provenance = provenance;
  double frontend_total = 0, backend_total = 0;
  for (const auto& [kind, s] : kinds) {
    double sum = 0;
    for (double v : s.y) sum += v;
    (is_frontend(s.part) ? frontend_total : backend_total) += sum;
  }
  for (const auto& [kind, s] : kinds) {
    RowCost cost = fit_kind(feature_names(s.part, kind), s.x, s.y);
    double sum = 0;
    for (double v : s.y) sum += v;
    const double total = is_frontend(s.part) ? frontend_total : backend_total;
    cost.measured_share = total > 0 ? sum / total : 0;
    (is_frontend(s.part) ? model.frontend : model.backend)[kind] = std::move(cost);
  }
  return model;
}

std::vector<std::string> fit_warnings(const HostCostModel& model) {
  std::vector<std::string> warnings;
  for (const auto* table : {&model.frontend, &model.backend}) {
    for (const auto& [kind, cost] : *table) {
      if (cost.samples >= 3 * cost.features.size()) continue;
      warnings.push_back(fmt::format(
          "kind '{}' fitted from {} row{}: its per-call cost alone (all {} costs need {} rows)",
          kind, cost.samples, cost.samples == 1 ? "" : "s", cost.features.size(),
          3 * cost.features.size()));
    }
  }
  return warnings;
}

HostCostModel replace_kinds(HostCostModel base, const HostCostModel& fitted,
                            const std::vector<std::string>& kinds) {
  if (base.suite != fitted.suite) {
    throw std::runtime_error(
        fmt::format("the base table is of suite v{}, the traces of v{}", base.suite, fitted.suite));
  }
  for (const std::string& kind : kinds) {
    bool found = false;
    for (auto [from, to] :
         {std::pair{&fitted.frontend, &base.frontend}, std::pair{&fitted.backend, &base.backend}}) {
      if (const auto it = from->find(kind); it != from->end()) {
        (*to)[kind] = it->second;
        found = true;
      }
    }
    if (!found) {
      throw std::runtime_error(fmt::format("kind '{}': the traces have no rows of it", kind));
    }
  }
  base.provenance += fmt::format("; {} re-fitted: {}", fmt::join(kinds, ", "), fitted.provenance);
  return base;
}

nlohmann::json compare_host_costs(const HostCostModel& model, const CostFitInput& trace) {
  struct Sums {
    std::size_t rows = 0;
    double measured = 0, modeled = 0, ss_res = 0, sum_y2 = 0;
  };
  std::map<std::string, Sums> kinds;
  for (const MeasuredRow& r : measured_rows(trace)) {
    Sums& s = kinds[r.row.kind];
    const double p = model.predict(r.row, trace.name);
    ++s.rows;
    s.measured += r.y;
    s.modeled += p;
    s.ss_res += (r.y - p) * (r.y - p);
    s.sum_y2 += r.y * r.y;
  }
  nlohmann::json out = nlohmann::json::array();
  for (const auto& [kind, s] : kinds) {
    const double mean = s.measured / static_cast<double>(s.rows);
    const double ss_tot = s.sum_y2 - static_cast<double>(s.rows) * mean * mean;
    out.push_back({{"kind", kind},
                   {"rows", s.rows},
                   {"measured_ns_per_suite_ms", s.measured},
                   {"modeled_ns_per_suite_ms", s.modeled},
                   {"r2", ss_tot > 0 ? 1 - s.ss_res / ss_tot : 1.0}});
  }
  return out;
}

}  // namespace edx::arch
