#include "workloads/backend/slam/lm_solver.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "workloads/backend/slam/factors.hpp"

namespace edx::backend::slam {
namespace {

using Vector6d = Eigen::Matrix<double, 6, 1>;

/// A landmark of the problem and its row of the normal equations.
struct LandmarkRow {
  Landmark* landmark = nullptr;
  double H_ll = 0;
  double b_l = 0;
  std::vector<std::pair<int, Vector6d>> H_lc;  ///< (keyframe slot, coupling with its pose)
  double H_lo = 0;  ///< coupling with the disparity offset (its right-image residuals)

  Vector6d& coupling(int slot) {
    for (auto& [s, v] : H_lc) {
      if (s == slot) return v;
    }
    H_lc.emplace_back(slot, Vector6d::Zero());
    return H_lc.back().second;
  }
};

struct NormalEquations {
  std::vector<LandmarkRow> rows;
  Eigen::MatrixXd H_cc;
  Eigen::VectorXd b_c;
  double cost = 0;
  int observations = 0;
};

bool usable(const Window& window, const Landmark& l) {
  return l.inverse_depth > 0 && l.inlier_count() >= 2 && window.slot(l.anchor_id) >= 0;
}

/// Index of the disparity offset in the camera block (after the keyframes), or -1.
int offset_index(const Window& window, const SlamOptions& options) {
  return options.estimate_disparity_offset
             ? static_cast<int>(window.keyframes.size()) * window.state_dim
             : -1;
}

/// Adds the prior r = r0 + J (x [-] x0) to (H, b) (when given) and returns its cost. Its
/// variables are the prior's keyframes (at slot * d) and, when it has one, the disparity offset.
double add_prior(const Window& window, const SlamOptions& options, Eigen::MatrixXd* H,
                 Eigen::VectorXd* b) {
  const Prior& prior = window.prior;
  if (prior.empty()) return 0;
  const Eigen::VectorXd r = prior.r0 + prior.J * window.prior_difference();
  if (H != nullptr) {
    const int d = window.state_dim;
    // (start in the prior's vector, start in H, length) of each variable block.
    std::vector<std::array<int, 3>> blocks;
    for (std::size_t k = 0; k < prior.keyframe_ids.size(); ++k) {
      blocks.push_back({static_cast<int>(k) * d, window.slot(prior.keyframe_ids[k]) * d, d});
    }
    if (prior.has_offset) {
      const int off = offset_index(window, options);
      if (off < 0) throw std::logic_error("slam prior: has the disparity offset, not estimated");
      blocks.push_back({static_cast<int>(prior.keyframe_ids.size()) * d, off, 1});
    }
    const Eigen::MatrixXd JtJ = prior.J.transpose() * prior.J;
    const Eigen::VectorXd Jtr = prior.J.transpose() * r;
    for (const auto& [p0, h0, len0] : blocks) {
      b->segment(h0, len0) -= Jtr.segment(p0, len0);
      for (const auto& [p1, h1, len1] : blocks) {
        H->block(h0, h1, len0, len1) += JtJ.block(p0, p1, len0, len1);
      }
    }
  }
  return 0.5 * r.squaredNorm();
}

/// IMU factors between consecutive keyframes; adds to (H, b) when given, returns the cost.
double add_imu(const Window& window, Eigen::MatrixXd* H, Eigen::VectorXd* b) {
  if (window.state_dim != 15) return 0;
  double cost = 0;
  for (std::size_t k = 1; k < window.keyframes.size(); ++k) {
    const KeyframeState& i = window.keyframes[k - 1];
    const KeyframeState& j = window.keyframes[k];
    if (!j.imu_from_previous) continue;
    const Eigen::Matrix<double, 15, 15> info = imu_information(*j.imu_from_previous);
    if (H == nullptr) {
      const Eigen::Matrix<double, 15, 1> r =
          imu_residual(*j.imu_from_previous, i, j, window.gravity);
      cost += 0.5 * r.dot(info * r);
      continue;
    }
    Eigen::Matrix<double, 15, 1> r;
    Eigen::Matrix<double, 15, 30> J;
    linearize_imu(*j.imu_from_previous, i, j, window.gravity, r, J);
    cost += 0.5 * r.dot(info * r);
    const Eigen::Matrix<double, 30, 30> JtWJ = J.transpose() * info * J;
    const Eigen::Matrix<double, 30, 1> JtWr = J.transpose() * info * r;
    const int a = static_cast<int>(k - 1) * 15;
    H->block<15, 15>(a, a) += JtWJ.block<15, 15>(0, 0);
    H->block<15, 15>(a, a + 15) += JtWJ.block<15, 15>(0, 15);
    H->block<15, 15>(a + 15, a) += JtWJ.block<15, 15>(15, 0);
    H->block<15, 15>(a + 15, a + 15) += JtWJ.block<15, 15>(15, 15);
    b->segment<30>(a) -= JtWr;
  }
  return cost;
}

/// Zero-mean prior on the disparity offset, r = delta / sigma; adds to (H, b) when given.
double add_offset_prior(const Window& window, const SlamOptions& options, Eigen::MatrixXd* H,
                        Eigen::VectorXd* b) {
  if (!options.estimate_disparity_offset) return 0;
  const double s = 1.0 / options.disparity_offset_sigma_px;
  const double r = s * window.disparity_offset_px;
  if (H != nullptr) {
    const int o = offset_index(window, options);
    (*H)(o, o) += s * s;
    (*b)(o) -= s * r;
  }
  return 0.5 * r * r;
}

NormalEquations linearize(Window& window, const SlamOptions& options) {
  const int d = window.state_dim;
  const int off = offset_index(window, options);
  const int C = static_cast<int>(window.keyframes.size()) * d + (off >= 0 ? 1 : 0);
  NormalEquations ne;
  ne.H_cc = Eigen::MatrixXd::Zero(C, C);
  ne.b_c = Eigen::VectorXd::Zero(C);
  ReprojectionTerm t;
  for (auto& [id, landmark] : window.landmarks) {
    if (!usable(window, landmark)) continue;
    LandmarkRow row;
    row.landmark = &landmark;
    const int a = window.slot(landmark.anchor_id);
    for (const Observation& o : landmark.observations) {
      if (!o.inlier || !linearize_reprojection(window, landmark, o, options.pixel_sigma, t)) {
        continue;
      }
      ++ne.observations;
      // Rows past t.dim are zero in r and every Jacobian, so the full 4-row blocks are used.
      const Eigen::Vector4d& r = t.r;
      const RobustWeight w = huber(r.norm(), options.huber_threshold);
      ne.cost += w.cost;
      const Eigen::Vector4d& J_rho = t.J_rho;
      row.H_ll += w.weight * J_rho.squaredNorm();
      row.b_l -= w.weight * J_rho.dot(r);
      const Eigen::Vector4d& J_o = t.J_offset;
      const bool has_offset = off >= 0 && J_o.squaredNorm() > 0;
      if (has_offset) {
        row.H_lo += w.weight * J_rho.dot(J_o);
        ne.H_cc(off, off) += w.weight * J_o.squaredNorm();
        ne.b_c(off) -= w.weight * J_o.dot(r);
      }
      if (t.same_frame) continue;
      const int j = window.slot(o.keyframe_id);
      const Eigen::Matrix<double, 4, 6>&Ja = t.J_anchor, &Jj = t.J_target;
      ne.H_cc.block<6, 6>(a * d, a * d) += w.weight * Ja.transpose() * Ja;
      ne.H_cc.block<6, 6>(a * d, j * d) += w.weight * Ja.transpose() * Jj;
      ne.H_cc.block<6, 6>(j * d, a * d) += w.weight * Jj.transpose() * Ja;
      ne.H_cc.block<6, 6>(j * d, j * d) += w.weight * Jj.transpose() * Jj;
      ne.b_c.segment<6>(a * d) -= w.weight * Ja.transpose() * r;
      ne.b_c.segment<6>(j * d) -= w.weight * Jj.transpose() * r;
      row.coupling(a) += w.weight * Ja.transpose() * J_rho;
      row.coupling(j) += w.weight * Jj.transpose() * J_rho;
      if (has_offset) {
        const Vector6d ha = w.weight * Ja.transpose() * J_o, hj = w.weight * Jj.transpose() * J_o;
        ne.H_cc.block<6, 1>(a * d, off) += ha;
        ne.H_cc.block<1, 6>(off, a * d) += ha.transpose();
        ne.H_cc.block<6, 1>(j * d, off) += hj;
        ne.H_cc.block<1, 6>(off, j * d) += hj.transpose();
      }
    }
    if (row.H_ll > 0) ne.rows.push_back(std::move(row));
  }
  ne.cost += add_imu(window, &ne.H_cc, &ne.b_c);
  ne.cost += add_prior(window, options, &ne.H_cc, &ne.b_c);
  ne.cost += add_offset_prior(window, options, &ne.H_cc, &ne.b_c);
  return ne;
}

struct Snapshot {
  std::vector<KeyframeState> keyframes;
  std::vector<double> inverse_depths;
  double disparity_offset_px = 0;
};

}  // namespace

double window_cost(const Window& window, const SlamOptions& options) {
  double cost = 0;
  ReprojectionTerm t;
  for (const auto& [id, landmark] : window.landmarks) {
    if (!usable(window, landmark)) continue;
    for (const Observation& o : landmark.observations) {
      if (!o.inlier || !linearize_reprojection(window, landmark, o, options.pixel_sigma, t)) {
        continue;
      }
      cost += huber(t.r.norm(), options.huber_threshold).cost;
    }
  }
  return cost + add_imu(window, nullptr, nullptr) + add_prior(window, options, nullptr, nullptr) +
         add_offset_prior(window, options, nullptr, nullptr);
}

/// The Schur complement's work as the dense primitives of the paper's matrix units (Table II),
/// which the loop below computes block-sparsely: with W = H_cl (C x L) and D = the damped H_ll
/// (diagonal, L), D^-1 (L reciprocals), T = W D^-1 (a column scaling: one product an entry),
/// S = H_cc - T W^T (C x C of L, symmetric) and s = b_c - T b_l (C x 1 of L). The kernel's detail
/// counts W's non-zero 6-blocks (coupling_blocks), the share a block-sparse unit would compute.
static void record_schur_ops(KernelRecorder& recorder, trace::KernelRecord& kernel,
                             const NormalEquations& ne, std::size_t landmarks, int cameras) {
  namespace f = trace::op_flags;
  const auto L = static_cast<std::int64_t>(landmarks);
  const std::int64_t C = cameras;
  recorder.describe(trace::Op::Inverse, L, L, 0, f::kDiagonal | f::kSymmetric);
  recorder.describe(trace::Op::Gemm, C, L, 1, 0);
  recorder.describe(trace::Op::Gemm, C, C, L, f::kSymmetric);
  recorder.describe(trace::Op::Gemm, C, 1, L, 0);
  std::size_t blocks = 0;
  for (const LandmarkRow& row : ne.rows) blocks += row.H_lc.size();
  kernel.detail_json = "{\"coupling_blocks\":" + std::to_string(blocks) + "}";
}

LmReport optimize_window(Window& window, const SlamOptions& options, KernelRecorder& recorder) {
  LmReport report;
  const int d = window.state_dim;
  const int K = static_cast<int>(window.keyframes.size());
  const int off = offset_index(window, options);
  const int C = K * d + (off >= 0 ? 1 : 0);
  double lambda = options.lm_initial_lambda, nu = 2.0;
  bool relinearize = true;
  NormalEquations ne;
  for (int it = 0; it < options.lm_max_iterations; ++it) {
    if (relinearize) {
      auto k = recorder.kernel("linearization");
      ne = linearize(window, options);
      k.record().m = ne.observations;
      k.record().n = static_cast<std::int64_t>(ne.rows.size()) + C;
      if (it == 0) {
        report.initial_cost = ne.cost;
        report.landmarks = static_cast<int>(ne.rows.size());
        report.observations = ne.observations;
      }
    }
    const std::size_t L = ne.rows.size();
    Eigen::VectorXd H_ll_damped(static_cast<Eigen::Index>(L));
    Eigen::MatrixXd S;
    Eigen::VectorXd s;
    {
      auto k = recorder.kernel("schur_complement");
      k.record().m = static_cast<std::int64_t>(L);
      k.record().n = C;
      record_schur_ops(recorder, k.record(), ne, L, C);
      S = ne.H_cc;
      S.diagonal() += lambda * ne.H_cc.diagonal();
      S.diagonal().array() += 1e-9;
      s = ne.b_c;
      for (std::size_t l = 0; l < L; ++l) {
        const LandmarkRow& row = ne.rows[l];
        const double h = row.H_ll * (1 + lambda) + 1e-12;
        H_ll_damped(static_cast<Eigen::Index>(l)) = h;
        for (const auto& [s1, v1] : row.H_lc) {
          s.segment<6>(s1 * d) -= v1 * (row.b_l / h);
          for (const auto& [s2, v2] : row.H_lc) {
            S.block<6, 6>(s1 * d, s2 * d) -= v1 * v2.transpose() / h;
          }
          if (off >= 0) {
            S.block<6, 1>(s1 * d, off) -= v1 * (row.H_lo / h);
            S.block<1, 6>(off, s1 * d) -= v1.transpose() * (row.H_lo / h);
          }
        }
        if (off >= 0) {
          S(off, off) -= row.H_lo * row.H_lo / h;
          s(off) -= row.H_lo * row.b_l / h;
        }
      }
    }
    Eigen::VectorXd dx_c, dx_l(static_cast<Eigen::Index>(L));
    {
      auto k = recorder.kernel("solve");
      k.record().m = C;
      k.record().n = static_cast<std::int64_t>(L);
      dx_c = S.ldlt().solve(s);
      for (std::size_t l = 0; l < L; ++l) {
        const LandmarkRow& row = ne.rows[l];
        double rhs = row.b_l;
        for (const auto& [slot, v] : row.H_lc) rhs -= v.dot(dx_c.segment<6>(slot * d));
        if (off >= 0) rhs -= row.H_lo * dx_c(off);
        dx_l(static_cast<Eigen::Index>(l)) = rhs / H_ll_damped(static_cast<Eigen::Index>(l));
      }
    }
    auto k = recorder.kernel("lm_iteration");
    k.record().m = static_cast<std::int64_t>(L);
    k.record().n = C;
    ++report.iterations;
    if (!dx_c.allFinite() || !dx_l.allFinite()) break;
    // Predicted decrease of the damped quadratic model.
    double predicted = dx_c.dot(lambda * ne.H_cc.diagonal().cwiseProduct(dx_c) + ne.b_c);
    for (std::size_t l = 0; l < L; ++l) {
      const auto i = static_cast<Eigen::Index>(l);
      predicted += dx_l(i) * (lambda * ne.rows[l].H_ll * dx_l(i) + ne.rows[l].b_l);
    }
    predicted *= 0.5;
    Snapshot saved;
    for (const KeyframeState& kf : window.keyframes)
      saved.keyframes.push_back(kf.navigation_state());
    for (std::size_t l = 0; l < L; ++l)
      saved.inverse_depths.push_back(ne.rows[l].landmark->inverse_depth);
    saved.disparity_offset_px = window.disparity_offset_px;
    if (off >= 0) window.disparity_offset_px += dx_c(off);
    for (int slot = 0; slot < K; ++slot) {
      window.keyframes[static_cast<std::size_t>(slot)].apply_increment(dx_c.segment(slot * d, d),
                                                                       d);
    }
    for (std::size_t l = 0; l < L; ++l) {
      ne.rows[l].landmark->inverse_depth += dx_l(static_cast<Eigen::Index>(l));
    }
    const double new_cost = window_cost(window, options);
    const double gain = predicted > 0 ? (ne.cost - new_cost) / predicted : -1;
    if (gain > 0 && std::isfinite(new_cost)) {
      ++report.accepted;
      const double relative = (ne.cost - new_cost) / std::max(ne.cost, 1e-12);
      ne.cost = new_cost;
      lambda *= std::max(1.0 / 3.0, 1.0 - std::pow(2 * gain - 1, 3));
      nu = 2;
      relinearize = true;
      if (relative < options.lm_min_relative_decrease) break;
    } else {
      for (int slot = 0; slot < K; ++slot) {
        KeyframeState& kf = window.keyframes[static_cast<std::size_t>(slot)];
        const KeyframeState& old = saved.keyframes[static_cast<std::size_t>(slot)];
        kf.R = old.R;
        kf.p = old.p;
        kf.v = old.v;
        kf.ba = old.ba;
        kf.bg = old.bg;
      }
      for (std::size_t l = 0; l < L; ++l)
        ne.rows[l].landmark->inverse_depth = saved.inverse_depths[l];
      window.disparity_offset_px = saved.disparity_offset_px;
      lambda *= nu;
      nu *= 2;
      relinearize = false;
    }
  }
  report.final_cost = ne.cost;
  return report;
}

int reject_outliers(Window& window, const SlamOptions& options) {
  int rejected = 0;
  ReprojectionTerm t;
  for (auto it = window.landmarks.begin(); it != window.landmarks.end();) {
    Landmark& landmark = it->second;
    const double depth = 1.0 / landmark.inverse_depth;
    if (!(landmark.inverse_depth > 0) || depth < options.min_landmark_depth_m ||
        depth > 10 * options.max_landmark_depth_m) {
      it = window.landmarks.erase(it);
      continue;
    }
    for (Observation& o : landmark.observations) {
      if (!o.inlier) continue;
      // Pixel errors: the whitened residual times sigma, per image.
      if (!linearize_reprojection(window, landmark, o, 1.0, t)) {
        o.inlier = false;
        ++rejected;
        continue;
      }
      for (int row = 0; row < t.dim; row += 2) {
        if (t.r.segment<2>(row).norm() > options.outlier_px) {
          o.inlier = false;
          ++rejected;
          break;
        }
      }
    }
    ++it;
  }
  return rejected;
}

}  // namespace edx::backend::slam
