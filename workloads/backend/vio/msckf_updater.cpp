#include "workloads/backend/vio/msckf_updater.hpp"

#include <fmt/format.h>

#include <Eigen/Cholesky>
#include <Eigen/QR>
#include <nlohmann/json.hpp>

#include "workloads/backend/vio/chi_square.hpp"
#include "workloads/backend/vio/ekf_update.hpp"
#include "workloads/backend/vio/track_noise.hpp"
#include "workloads/backend/vio/triangulation.hpp"

namespace edx::backend::vio {
namespace {

/// A track with the clones it was seen in and its residual rows.
struct FeatureRows {
  const FeatureTrack* track = nullptr;
  std::vector<Observation> observations;  ///< those whose clone is in the window
  std::vector<int> clones;                ///< clone index of each observation
  Eigen::Vector3d p_W = Eigen::Vector3d::Zero();
  Eigen::MatrixXd H_x, H_f;
  Eigen::VectorXd r;
};

}  // namespace

MsckfUpdater::MsckfUpdater(const VioOptions& options, double baseline_m, double focal_px)
    : options_(options),
      baseline_m_(baseline_m),
      focal_px_(focal_px),
      sigma_(options.effective_pixel_sigma() / focal_px),
      gate_sigma_(options.pixel_sigma / focal_px) {}

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
  const int n = state.dim();
  // kRandomWalk: rows whitened by the track's covariance, so unit variance at the gate and the
  // inflation (1 + rho) / (1 - rho) in the update (sigma_^2 / gate_sigma_^2).
  const bool whiten = options_.track_noise == VioOptions::TrackNoise::kRandomWalk;
  const double sigma2 = whiten ? (sigma_ * sigma_) / (gate_sigma_ * gate_sigma_) : sigma_ * sigma_;
  const double gate_sigma2 = whiten ? 1.0 : gate_sigma_ * gate_sigma_;

  // Triangulation of every track from the clone cameras.
  std::vector<FeatureRows> features;
  {
    auto kernel = recorder.kernel("triangulation");
    TriangulationOptions tri;
    tri.baseline_m = baseline_m_;
    tri.min_depth_m = options_.min_depth_m;
    tri.max_depth_m = options_.max_depth_m;
    tri.max_baseline_ratio = options_.max_depth_baseline_ratio;
    tri.max_rms = options_.max_triangulation_rms_px / focal_px_;
    tri.iterations = options_.triangulation_iterations;
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
  }
  report.triangulated = static_cast<int>(features.size());
  if (features.empty()) return report;
  // Keep the longest tracks when there are too many (ties: by id, deterministic).
  if (static_cast<int>(features.size()) > options_.max_features_per_update) {
    std::stable_sort(features.begin(), features.end(), [](const auto& a, const auto& b) {
      return a.observations.size() > b.observations.size();
    });
    features.resize(static_cast<std::size_t>(options_.max_features_per_update));
  }

  // Measurement Jacobians.
  {
    auto kernel = recorder.kernel("jacobians");
    int rows_total = 0;
    Eigen::VectorXd z;
    Eigen::MatrixXd dz;
    std::vector<double> depths;  ///< the point's depth in each observation's camera
    double whitening_flops = 0;  ///< of the random-walk whitening (docs/TRACE.md)
    for (FeatureRows& f : features) {
      int rows = 0;
      for (const Observation& o : f.observations) rows += o.rows();
      f.H_x = Eigen::MatrixXd::Zero(rows, n);
      f.H_f.resize(rows, 3);
      f.r.resize(rows);
      int row = 0;
      depths.resize(f.observations.size());
      for (std::size_t i = 0; i < f.observations.size(); ++i) {
        const Observation& o = f.observations[i];
        const Clone& clone = state.clones[static_cast<std::size_t>(f.clones[i])];
        const Eigen::Vector3d d = f.p_W - clone.p_WI;
        const Eigen::Vector3d p_I = clone.R_WI.transpose() * d;
        const Eigen::Vector3d q = p_I - state.p_IC;
        const Eigen::Vector3d p_C = state.R_IC.transpose() * q;
        project_stereo(p_C, baseline_m_, o.stereo, z, dz);
        depths[i] = p_C.z();
        const int k = o.rows();
        const Eigen::MatrixXd J_world = dz * state.R_IC.transpose() * clone.R_WI.transpose();
        const int at = VioState::clone_index(static_cast<std::size_t>(f.clones[i]));
        // FEJ: the clone position of [d]x at its first estimate, so that H_x N_yaw lies in the
        // span of H_f and the null-space projection removes the unobservable yaw exactly.
        f.H_x.block(row, at, k, 3) = J_world * skew(f.p_W - clone.p_lin());
        f.H_x.block(row, at + 3, k, 3) = -J_world;
        if (options_.estimate_extrinsics) {
          f.H_x.block(row, kExtTheta, k, 3) = dz * state.R_IC.transpose() * skew(q);
          f.H_x.block(row, kExtPos, k, 3) = -dz * state.R_IC.transpose();
        }
        f.H_f.middleRows(row, k) = J_world;
        f.r.segment(row, k) = measured(o) - z;
        row += k;
      }
      if (whiten) {  // L^-1 r, L^-1 H_x, L^-1 H_f with L L^T = the track's covariance
        const Eigen::LLT<Eigen::MatrixXd> llt(
            track_covariance(f.observations, options_.random_walk, focal_px_, depths));
        // L^-1 keeps H_x's zero columns zero: solve only on the columns the feature touches.
        std::vector<Eigen::Index> cols;
        for (Eigen::Index c = 0; c < n; ++c)
          if (!f.H_x.col(c).isZero(0.0)) cols.push_back(c);
        Eigen::MatrixXd touched = f.H_x(Eigen::all, cols);
        llt.matrixL().solveInPlace(touched);
        f.H_x(Eigen::all, cols) = touched;
        llt.matrixL().solveInPlace(f.r);
        llt.matrixL().solveInPlace(f.H_f);
        // Cholesky rows^3 / 3, the solves rows^2 per right-hand side (H_x's touched, H_f, r).
        const double r = rows;
        whitening_flops += r * r * r / 3.0 + r * r * static_cast<double>(cols.size() + 4);
      }
      rows_total += rows;
    }
    kernel.record().m = rows_total;
    kernel.record().n = n;
    kernel.record().k = static_cast<std::int64_t>(features.size());
    if (whiten) {
      kernel.record().detail_json = nlohmann::json{{"whitening_flops", whitening_flops}}.dump();
    }
  }

  // Left null-space projection and the chi-square gate.
  Eigen::MatrixXd H;
  Eigen::VectorXd r;
  std::vector<Eigen::Index> feature_rows;  ///< rows of each accepted feature, in H's order
  {
    auto kernel = recorder.kernel("nullspace_projection");
    std::vector<FeatureRows*> accepted;
    int rows_total = 0;
    for (FeatureRows& f : features) {
      const Eigen::Index rows = f.H_f.rows();
      if (rows <= 3) continue;
      Eigen::HouseholderQR<Eigen::MatrixXd> qr(f.H_f);
      f.H_x.applyOnTheLeft(qr.householderQ().adjoint());
      f.r.applyOnTheLeft(qr.householderQ().adjoint());
      f.H_x = f.H_x.bottomRows(rows - 3).eval();
      f.r = f.r.tail(rows - 3).eval();
      // Gate: gamma = r^T (H P H^T + sigma^2 I)^-1 r on the columns H touches.
      std::vector<int> cols;
      for (int c = 0; c < n; ++c)
        if (!f.H_x.col(c).isZero(0.0)) cols.push_back(c);
      Eigen::MatrixXd Hs(f.H_x.rows(), static_cast<Eigen::Index>(cols.size()));
      Eigen::MatrixXd Ps(cols.size(), cols.size());
      for (std::size_t a = 0; a < cols.size(); ++a) {
        Hs.col(static_cast<Eigen::Index>(a)) = f.H_x.col(cols[a]);
        for (std::size_t b = 0; b < cols.size(); ++b)
          Ps(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(b)) =
              state.P(cols[a], cols[b]);
      }
      // Gate at the white per-observation noise pixel_sigma, not at the update's inflated sigma:
      // the slow drift the inflation stands for is mostly absorbed by the point and passes, while
      // a track whose residual white pixel_sigma noise cannot explain (a sliding feature, a wrong
      // stereo match) is an outlier. Gating at sigma_eff (3 px) let nearly all of them in.
      Eigen::MatrixXd S = Hs * Ps * Hs.transpose();
      S.diagonal().array() += gate_sigma2;
      const double gamma = f.r.dot(S.ldlt().solve(f.r));
      if (gamma > chi2_threshold(static_cast<int>(f.r.size()))) continue;
      report.gamma_sum += gamma;
      report.gamma_dof += static_cast<int>(f.r.size());
      accepted.push_back(&f);
      rows_total += static_cast<int>(f.r.size());
    }
    H.resize(rows_total, n);
    r.resize(rows_total);
    int row = 0;
    for (FeatureRows* f : accepted) {
      const Eigen::Index k = f->r.size();
      H.middleRows(row, k) = f->H_x;
      r.segment(row, k) = f->r;
      feature_rows.push_back(k);
      row += static_cast<int>(k);
    }
    report.accepted = static_cast<int>(accepted.size());
    kernel.record().m = rows_total;
    kernel.record().n = n;
    kernel.record().k = report.accepted;
  }
  report.rows = static_cast<int>(H.rows());
  if (H.rows() == 0) return report;

  // Optional measurement compression when the rows outnumber the state columns H touches (the
  // QR runs on those columns only; the others are zero and stay zero).
  std::vector<int> cols;
  if (options_.measurement_compression) {
    for (int c = 0; c < n; ++c)
      if (!H.col(c).isZero(0.0)) cols.push_back(c);
  }
  const int used_cols = static_cast<int>(cols.size());
  const bool compressed = options_.measurement_compression && H.rows() > used_cols;
  if (compressed) {
    auto kernel = recorder.kernel("compression");
    kernel.record().m = H.rows();
    kernel.record().n = used_cols;
    Eigen::MatrixXd Hc(H.rows(), used_cols);
    for (int a = 0; a < used_cols; ++a) Hc.col(a) = H.col(cols[static_cast<std::size_t>(a)]);
    Eigen::HouseholderQR<Eigen::MatrixXd> qr(Hc);
    r.applyOnTheLeft(qr.householderQ().adjoint());
    const Eigen::MatrixXd T = qr.matrixQR().topRows(used_cols).triangularView<Eigen::Upper>();
    H = Eigen::MatrixXd::Zero(used_cols, n);
    for (int a = 0; a < used_cols; ++a) H.col(cols[static_cast<std::size_t>(a)]) = T.col(a);
    r = r.head(used_cols).eval();
  }
  report.rows_used = static_cast<int>(H.rows());

  // Groups of whole features of at most max_gain_rows rows each (one group when compressed).
  const Eigen::Index max_rows = options_.max_gain_rows > 0 ? options_.max_gain_rows : n;
  std::vector<Eigen::Index> group_rows;
  if (compressed) {
    group_rows.push_back(H.rows());
  } else {
    for (const Eigen::Index k : feature_rows) {
      if (group_rows.empty() || group_rows.back() + k > max_rows)
        group_rows.push_back(k);
      else
        group_rows.back() += k;
    }
  }

  // Sequential update at one linearization point: dx_g = K_g (r_g - H_g dx), P <- P - K_g H_g P.
  Eigen::VectorXd dx = Eigen::VectorXd::Zero(n);
  Eigen::MatrixXd P = state.P;
  Eigen::Index begin = 0;
  for (const Eigen::Index rows : group_rows) {
    const Eigen::MatrixXd H_g = H.middleRows(begin, rows);
    const Eigen::VectorXd r_g = r.segment(begin, rows) - H_g * dx;
    begin += rows;
    KalmanGain gain;
    {
      auto kernel = recorder.kernel("kalman_gain", /*accelerable=*/true);
      kernel.record().m = rows;
      kernel.record().n = n;
      gain = kalman_gain(P, H_g, Eigen::VectorXd::Constant(rows, sigma2), &recorder);
    }
    if (!gain.ok) break;
    auto kernel = recorder.kernel("covariance_update");
    kernel.record().m = rows;
    kernel.record().n = n;
    if (!update_covariance(P, gain)) break;
    dx += gain.K * r_g;
    ++report.gains;
  }
  if (report.gains == 0) return report;
  state.P = std::move(P);
  state.correct(dx);
  report.updated = true;
  return report;
}

}  // namespace edx::backend::vio
