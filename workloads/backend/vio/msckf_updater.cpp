#include "workloads/backend/vio/msckf_updater.hpp"

#include <fmt/format.h>

#include <Eigen/Cholesky>
#include <Eigen/QR>
#include <map>
#include <nlohmann/json.hpp>
#include <utility>

#include "workloads/backend/vio/chi_square.hpp"
#include "workloads/backend/vio/ekf_update.hpp"
#include "workloads/backend/vio/track_noise.hpp"
#include "workloads/backend/vio/triangulation.hpp"

namespace edx::backend::vio {

/// A track with the clones it was seen in and its residual rows.
struct FeatureRows {
  const FeatureTrack* track = nullptr;
  std::vector<Observation> observations;  ///< those whose clone is in the window
  std::vector<int> clones;                ///< clone index of each observation
  Eigen::Vector3d p_W = Eigen::Vector3d::Zero();
  Eigen::MatrixXd H_x, H_f;
  Eigen::VectorXd r;
};

namespace {

/// The columns of H that are not all zero (the state entries the rows depend on).
std::vector<Eigen::Index> touched_columns(const Eigen::MatrixXd& H) {
  std::vector<Eigen::Index> cols;
  for (Eigen::Index c = 0; c < H.cols(); ++c)
    if (!H.col(c).isZero(0.0)) cols.push_back(c);
  return cols;
}

/// Keeps the `max_features` longest tracks when there are more (ties: by id, deterministic).
void keep_longest(std::vector<FeatureRows>& features, int max_features) {
  if (static_cast<int>(features.size()) <= max_features) return;
  std::stable_sort(features.begin(), features.end(), [](const auto& a, const auto& b) {
    return a.observations.size() > b.observations.size();
  });
  features.resize(static_cast<std::size_t>(max_features));
}

/// The rows of one feature, per observation in clone j (msckf_updater.hpp):
///   H_x[clone j] = [J_world [p_W - p_WIj(first estimate)]x, -J_world],  H_f = J_world,
///   J_world = dz/dp_C R_IC^T R_WIj^T,  r = z_measured - z(p_C),
/// and with estimate_extrinsics H_x[IC] = [dz/dp_C R_IC^T [q]x, -dz/dp_C R_IC^T].
/// `depths` gets the point's depth in each observation's camera.
void feature_jacobians(const VioState& state, double baseline_m, bool estimate_extrinsics,
                       FeatureRows& f, std::vector<double>& depths) {
  int rows = 0;
  for (const Observation& o : f.observations) rows += o.rows();
  f.H_x = Eigen::MatrixXd::Zero(rows, state.dim());
  f.H_f.resize(rows, 3);
  f.r.resize(rows);
  Eigen::VectorXd z;
  Eigen::MatrixXd dz;
  int row = 0;
  depths.resize(f.observations.size());
  for (std::size_t i = 0; i < f.observations.size(); ++i) {
    const Observation& o = f.observations[i];
    const Clone& clone = state.clones[static_cast<std::size_t>(f.clones[i])];
    const Eigen::Vector3d d = f.p_W - clone.p_WI;
    const Eigen::Vector3d p_I = clone.R_WI.transpose() * d;
    const Eigen::Vector3d q = p_I - state.p_IC;
    const Eigen::Vector3d p_C = state.R_IC.transpose() * q;
    project_stereo(p_C, baseline_m, o.stereo, z, dz);
    depths[i] = p_C.z();
    const int k = o.rows();
    const Eigen::MatrixXd J_world = dz * state.R_IC.transpose() * clone.R_WI.transpose();
    const int at = VioState::clone_index(static_cast<std::size_t>(f.clones[i]));
    // FEJ: the clone position of [d]x at its first estimate, so that H_x N_yaw lies in the
    // span of H_f and the null-space projection removes the unobservable yaw exactly.
    f.H_x.block(row, at, k, 3) = J_world * skew(f.p_W - clone.p_lin());
    f.H_x.block(row, at + 3, k, 3) = -J_world;
    if (estimate_extrinsics) {
      f.H_x.block(row, kExtTheta, k, 3) = dz * state.R_IC.transpose() * skew(q);
      f.H_x.block(row, kExtPos, k, 3) = -dz * state.R_IC.transpose();
    }
    f.H_f.middleRows(row, k) = J_world;
    f.r.segment(row, k) = measured(o) - z;
    row += k;
  }
}

/// L^-1 r, L^-1 H_x, L^-1 H_f with L L^T = the track's covariance (track_noise.hpp). Returns
/// the flops of the whitening (docs/TRACE.md): Cholesky rows^3 / 3, the solves rows^2 per
/// right-hand side (H_x's touched columns, H_f, r).
double whiten_rows(FeatureRows& f, const RandomWalkTrackNoise& noise, double focal_px,
                   const std::vector<double>& depths) {
  const Eigen::LLT<Eigen::MatrixXd> llt(track_covariance(f.observations, noise, focal_px, depths));
  // L^-1 keeps H_x's zero columns zero: solve only on the columns the feature touches.
  const std::vector<Eigen::Index> cols = touched_columns(f.H_x);
  Eigen::MatrixXd touched = f.H_x(Eigen::all, cols);
  llt.matrixL().solveInPlace(touched);
  f.H_x(Eigen::all, cols) = touched;
  llt.matrixL().solveInPlace(f.r);
  llt.matrixL().solveInPlace(f.H_f);
  const double r = static_cast<double>(f.r.size());
  return r * r * r / 3.0 + r * r * static_cast<double>(cols.size() + 4);
}

/// Left null-space projection: H_f = Q [R1; 0] (Householder QR); H_x, r <- rows 3.. of Q^T H_x,
/// Q^T r, which no longer depend on the point.
void project_out_point(FeatureRows& f) {
  const Eigen::Index rows = f.H_f.rows();
  Eigen::HouseholderQR<Eigen::MatrixXd> qr(f.H_f);
  f.H_x.applyOnTheLeft(qr.householderQ().adjoint());
  f.r.applyOnTheLeft(qr.householderQ().adjoint());
  f.H_x = f.H_x.bottomRows(rows - 3).eval();
  f.r = f.r.tail(rows - 3).eval();
}

/// The chi-square gate's figure of one feature and the state columns its rows touch.
struct Innovation {
  double gamma = 0;
  Eigen::Index columns = 0;
};

/// The normalized innovation gamma = r^T (H P H^T + sigma^2 I)^-1 r, on the columns H touches.
Innovation normalized_innovation(const FeatureRows& f, const Eigen::MatrixXd& P, double variance) {
  const std::vector<Eigen::Index> cols = touched_columns(f.H_x);
  Eigen::MatrixXd Hs(f.H_x.rows(), static_cast<Eigen::Index>(cols.size()));
  Eigen::MatrixXd Ps(cols.size(), cols.size());
  for (std::size_t a = 0; a < cols.size(); ++a) {
    Hs.col(static_cast<Eigen::Index>(a)) = f.H_x.col(cols[a]);
    for (std::size_t b = 0; b < cols.size(); ++b)
      Ps(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(b)) = P(cols[a], cols[b]);
  }
  Eigen::MatrixXd S = Hs * Ps * Hs.transpose();
  S.diagonal().array() += variance;
  return {f.r.dot(S.ldlt().solve(f.r)), static_cast<Eigen::Index>(cols.size())};
}

/// The matrix ops of the null-space projection kernel (docs/TRACE.md), one batch per shape:
/// what project_out_point and normalized_innovation compute, feature by feature.
class ProjectionOps {
 public:
  /// A feature of `rows` rows (before the projection) projected in a state of `state_dim`.
  void add_projection(Eigen::Index rows) { ++projections_[rows]; }
  /// Its gate on `rows` projected rows touching `columns` state columns.
  void add_gate(Eigen::Index rows, Eigen::Index columns) { ++gates_[{rows, columns}]; }

  /// Records them: per feature of R rows, H_f = QR (qr R x 3) and Qᵀ[H_x r] in the compact WY
  /// form Q = I - V T Vᵀ (gemm 3 x (n+1) x R: W = Vᵀ[H_x r]; gemm 3 x (n+1) x 3: Tᵀ W; gemm
  /// R x (n+1) x 3: [H_x r] - V TᵀW); per gate on r rows and c columns S = Hs Ps Hsᵀ + σ²I (gemm
  /// r x c x c with Ps symmetric, gemm r x r x c with a symmetric result), its LDLᵀ (ldlt r),
  /// the two triangular solves of S⁻¹r (trsv r, two) and rᵀ(S⁻¹r) (gemm 1 x 1 x r).
  void record(KernelRecorder& recorder, std::int64_t state_dim) const {
    namespace f = trace::op_flags;
    using trace::Op;
    const std::int64_t cols = state_dim + 1;
    for (const auto& [rows, count] : projections_) {
      recorder.describe(Op::Qr, rows, 3, 0, 0, count);
      recorder.describe(Op::Gemm, 3, cols, rows, f::kTransposeA, count);
      recorder.describe(Op::Gemm, 3, cols, 3, f::kUpper | f::kTransposeA, count);
      recorder.describe(Op::Gemm, rows, cols, 3, 0, count);
    }
    for (const auto& [shape, count] : gates_) {
      const auto [rows, columns] = shape;
      recorder.describe(Op::Gemm, rows, columns, columns, f::kSymmetric, count);
      recorder.describe(Op::Gemm, rows, rows, columns, f::kSymmetric | f::kTransposeB, count);
      recorder.describe(Op::Ldlt, rows, rows, 0, f::kSymmetric, count);
      recorder.describe(Op::Trsv, rows, 1, 0, f::kLower, 2 * count);
      recorder.describe(Op::Gemm, 1, 1, rows, f::kTransposeA, count);
    }
  }

 private:
  std::map<Eigen::Index, std::int64_t> projections_;
  std::map<std::pair<Eigen::Index, Eigen::Index>, std::int64_t> gates_;
};

/// Groups of whole features of at most max_rows rows each, in order (a feature larger than
/// max_rows is a group of its own).
std::vector<Eigen::Index> whole_feature_groups(const std::vector<Eigen::Index>& feature_rows,
                                               Eigen::Index max_rows) {
  std::vector<Eigen::Index> group_rows;
  for (const Eigen::Index k : feature_rows) {
    if (group_rows.empty() || group_rows.back() + k > max_rows)
      group_rows.push_back(k);
    else
      group_rows.back() += k;
  }
  return group_rows;
}

}  // namespace

MsckfUpdater::MsckfUpdater(const VioOptions& options, double baseline_m, double focal_px)
    : options_(options),
      baseline_m_(baseline_m),
      focal_px_(focal_px),
      sigma_(options.effective_pixel_sigma() / focal_px),
      gate_sigma_(options.pixel_sigma / focal_px),
      whiten_(options.track_noise == VioOptions::TrackNoise::kRandomWalk),
      update_variance_(whiten_ ? (sigma_ * sigma_) / (gate_sigma_ * gate_sigma_) : sigma_ * sigma_),
      gate_variance_(whiten_ ? 1.0 : gate_sigma_ * gate_sigma_) {}

double MsckfUpdater::chi2_threshold(int dof) {
  if (static_cast<int>(chi2_table_.size()) <= dof) {
    const int from = static_cast<int>(chi2_table_.size());
    chi2_table_.resize(static_cast<std::size_t>(dof) + 1, 0.0);
    for (int d = std::max(from, 1); d <= dof; ++d)
      chi2_table_[static_cast<std::size_t>(d)] = chi2_quantile(options_.chi2_confidence, d);
  }
  return chi2_table_[static_cast<std::size_t>(dof)];
}

UpdateReport MsckfUpdater::update(VioState& state, const std::vector<const FeatureTrack*>& tracks,
                                  KernelRecorder& recorder) {
  UpdateReport report;
  report.tracks = static_cast<int>(tracks.size());
  if (tracks.empty()) return report;
  std::vector<FeatureRows> features = triangulate_tracks(state, tracks, recorder);
  report.triangulated = static_cast<int>(features.size());
  if (features.empty()) return report;
  keep_longest(features, options_.max_features_per_update);
  measurement_jacobians(state, features, recorder);
  StackedRows rows = project_out_points(state, features, report, recorder);
  report.rows = static_cast<int>(rows.H.rows());
  if (rows.H.rows() == 0) return report;
  const bool compressed = options_.measurement_compression && compress(rows, state.dim(), recorder);
  report.rows_used = static_cast<int>(rows.H.rows());
  // One group when compressed, else whole features of at most max_gain_rows rows each.
  const Eigen::Index max_rows = options_.max_gain_rows > 0 ? options_.max_gain_rows : state.dim();
  const std::vector<Eigen::Index> group_rows =
      compressed ? std::vector<Eigen::Index>{rows.H.rows()}
                 : whole_feature_groups(rows.feature_rows, max_rows);
  sequential_update(state, rows, group_rows, report, recorder);
  return report;
}

std::vector<FeatureRows> MsckfUpdater::triangulate_tracks(
    const VioState& state, const std::vector<const FeatureTrack*>& tracks,
    KernelRecorder& recorder) const {
  auto kernel = recorder.kernel("triangulation");
  TriangulationOptions tri;
  tri.baseline_m = baseline_m_;
  tri.min_depth_m = options_.min_depth_m;
  tri.max_depth_m = options_.max_depth_m;
  tri.max_baseline_ratio = options_.max_depth_baseline_ratio;
  tri.max_rms = options_.max_triangulation_rms_px / focal_px_;
  tri.iterations = options_.triangulation_iterations;
  std::vector<FeatureRows> features;
  int observations = 0, iterations = 0;
  for (const FeatureTrack* track : tracks) {
    FeatureRows f;
    f.track = track;
    std::vector<CameraPose> cameras;
    for (const Observation& o : track->observations) {
      const int c = state.find_clone(o.t_ns);
      if (c < 0) continue;
      const Clone& clone = state.clones[static_cast<std::size_t>(c)];
      f.observations.push_back(o);
      f.clones.push_back(c);
      cameras.push_back({clone.R_WI * state.R_IC, clone.p_WI + clone.R_WI * state.p_IC});
    }
    if (static_cast<int>(f.observations.size()) < options_.min_track_length) continue;
    observations += static_cast<int>(f.observations.size());
    const auto point = triangulate(f.observations, cameras, tri);
    if (!point) continue;
    iterations += point->iterations;
    f.p_W = point->p_W;
    features.push_back(std::move(f));
  }
  kernel.record().m = static_cast<std::int64_t>(tracks.size());
  kernel.record().n = observations;
  kernel.record().k = iterations;
  kernel.record().detail_json =
      fmt::format(R"({{"triangulated":{}}})", static_cast<int>(features.size()));
  return features;
}

void MsckfUpdater::measurement_jacobians(const VioState& state, std::vector<FeatureRows>& features,
                                         KernelRecorder& recorder) const {
  auto kernel = recorder.kernel("jacobians");
  int rows_total = 0;
  std::vector<double> depths;  ///< the point's depth in each observation's camera
  double whitening_flops = 0;  ///< of the random-walk whitening (docs/TRACE.md)
  for (FeatureRows& f : features) {
    feature_jacobians(state, baseline_m_, options_.estimate_extrinsics, f, depths);
    if (whiten_) whitening_flops += whiten_rows(f, options_.random_walk, focal_px_, depths);
    rows_total += static_cast<int>(f.r.size());
  }
  kernel.record().m = rows_total;
  kernel.record().n = state.dim();
  kernel.record().k = static_cast<std::int64_t>(features.size());
  if (whiten_) {
    kernel.record().detail_json = nlohmann::json{{"whitening_flops", whitening_flops}}.dump();
  }
}

MsckfUpdater::StackedRows MsckfUpdater::project_out_points(const VioState& state,
                                                           std::vector<FeatureRows>& features,
                                                           UpdateReport& report,
                                                           KernelRecorder& recorder) {
  auto kernel = recorder.kernel("nullspace_projection");
  const int n = state.dim();
  std::vector<FeatureRows*> accepted;
  int rows_total = 0;
  ProjectionOps ops;
  for (FeatureRows& f : features) {
    if (f.H_f.rows() <= 3) continue;
    ops.add_projection(f.H_f.rows());
    project_out_point(f);
    // Gate at the white per-observation noise pixel_sigma, not at the update's inflated sigma:
    // the slow drift the inflation stands for is mostly absorbed by the point and passes, while
    // a track whose residual white pixel_sigma noise cannot explain (a sliding feature, a wrong
    // stereo match) is an outlier. Gating at sigma_eff (3 px) let nearly all of them in.
    const Innovation innovation = normalized_innovation(f, state.P, gate_variance_);
    ops.add_gate(f.r.size(), innovation.columns);
    const double gamma = innovation.gamma;
    if (gamma > chi2_threshold(static_cast<int>(f.r.size()))) continue;
    report.gamma_sum += gamma;
    report.gamma_dof += static_cast<int>(f.r.size());
    accepted.push_back(&f);
    rows_total += static_cast<int>(f.r.size());
  }
  StackedRows stacked;
  stacked.H.resize(rows_total, n);
  stacked.r.resize(rows_total);
  int row = 0;
  for (FeatureRows* f : accepted) {
    const Eigen::Index k = f->r.size();
    stacked.H.middleRows(row, k) = f->H_x;
    stacked.r.segment(row, k) = f->r;
    stacked.feature_rows.push_back(k);
    row += static_cast<int>(k);
  }
  report.accepted = static_cast<int>(accepted.size());
  ops.record(recorder, n);
  kernel.record().m = rows_total;
  kernel.record().n = n;
  kernel.record().k = report.accepted;
  return stacked;
}

bool MsckfUpdater::compress(StackedRows& rows, int state_dim, KernelRecorder& recorder) const {
  // The QR runs on the columns H touches only; the others are zero and stay zero.
  const std::vector<Eigen::Index> cols = touched_columns(rows.H);
  const int used_cols = static_cast<int>(cols.size());
  if (rows.H.rows() <= used_cols) return false;
  auto kernel = recorder.kernel("compression");
  kernel.record().m = rows.H.rows();
  kernel.record().n = used_cols;
  Eigen::MatrixXd Hc(rows.H.rows(), used_cols);
  for (int a = 0; a < used_cols; ++a) Hc.col(a) = rows.H.col(cols[static_cast<std::size_t>(a)]);
  Eigen::HouseholderQR<Eigen::MatrixXd> qr(Hc);
  rows.r.applyOnTheLeft(qr.householderQ().adjoint());
  // Its ops: qr m x c, then Qᵀr in the WY form (gemm c x 1 x m, c x 1 x c, m x 1 x c).
  namespace f = trace::op_flags;
  const std::int64_t m = rows.H.rows();
  recorder.describe(trace::Op::Qr, m, used_cols, 0, 0);
  recorder.describe(trace::Op::Gemm, used_cols, 1, m, f::kTransposeA);
  recorder.describe(trace::Op::Gemm, used_cols, 1, used_cols, f::kUpper | f::kTransposeA);
  recorder.describe(trace::Op::Gemm, m, 1, used_cols, 0);
  const Eigen::MatrixXd T = qr.matrixQR().topRows(used_cols).triangularView<Eigen::Upper>();
  rows.H = Eigen::MatrixXd::Zero(used_cols, state_dim);
  for (int a = 0; a < used_cols; ++a) rows.H.col(cols[static_cast<std::size_t>(a)]) = T.col(a);
  rows.r = rows.r.head(used_cols).eval();
  return true;
}

void MsckfUpdater::sequential_update(VioState& state, const StackedRows& rows,
                                     const std::vector<Eigen::Index>& group_rows,
                                     UpdateReport& report, KernelRecorder& recorder) const {
  // dx_g = K_g (r_g - H_g dx), P <- P - K_g H_g P, group after group.
  const int n = state.dim();
  Eigen::VectorXd dx = Eigen::VectorXd::Zero(n);
  Eigen::MatrixXd P = state.P;
  Eigen::Index begin = 0;
  for (const Eigen::Index group : group_rows) {
    const Eigen::MatrixXd H_g = rows.H.middleRows(begin, group);
    const Eigen::VectorXd r_g = rows.r.segment(begin, group) - H_g * dx;
    begin += group;
    KalmanGain gain;
    {
      auto kernel = recorder.kernel("kalman_gain", /*accelerable=*/true);
      kernel.record().m = group;
      kernel.record().n = n;
      gain = kalman_gain(P, H_g, Eigen::VectorXd::Constant(group, update_variance_), &recorder,
                         options_.precision);
    }
    if (!gain.ok) break;
    auto kernel = recorder.kernel("covariance_update");
    kernel.record().m = group;
    kernel.record().n = n;
    if (!update_covariance(P, gain, &recorder, options_.precision)) break;
    dx += gain.K * r_g;
    ++report.gains;
  }
  if (report.gains == 0) return;
  state.P = std::move(P);
  state.correct(dx);
  report.updated = true;
}

}  // namespace edx::backend::vio
