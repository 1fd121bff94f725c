#include "workloads/backend/slam/lm_solver.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <array>
#include <cmath>
#include <nlohmann/json.hpp>
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

/// The non-zero 6-blocks of H_cl: each landmark's couplings with the keyframes observing it.
std::size_t coupling_blocks(const NormalEquations& ne) {
  std::size_t blocks = 0;
  for (const LandmarkRow& row : ne.rows) blocks += row.H_lc.size();
  return blocks;
}

bool usable(const Window& window, const Landmark& l) {
  return l.inverse_depth > 0 && l.inlier_count() >= 2 && window.slot(l.anchor_id) >= 0;
}

/// Index of the disparity offset in the camera block (after the keyframes), or -1.
int offset_index(const Window& window, const SlamOptions& options) {
  return options.estimate_disparity_offset
             ? static_cast<int>(window.keyframes.size()) * window.state_dim
             : -1;
}

/// The prior's residual r = r0 + J (x [-] x0) (into `residual` when given) and its cost
/// 1/2 |r|².
double prior_residual(const Window& window, Eigen::VectorXd* residual) {
  const Prior& prior = window.prior;
  if (prior.empty()) return 0;
  const Eigen::VectorXd r = prior.r0 + prior.J * window.prior_difference();
  if (residual != nullptr) *residual = r;
  return 0.5 * r.squaredNorm();
}

/// Adds the prior's JᵀJ and -Jᵀr (r its residual) to (H, b). Its variables are the prior's
/// keyframes (at slot * d) and, when it has one, the disparity offset.
void add_prior_products(const Window& window, const SlamOptions& options, const Eigen::VectorXd& r,
                        Eigen::MatrixXd& H, Eigen::VectorXd& b) {
  const Prior& prior = window.prior;
  if (prior.empty()) return;
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
    b.segment(h0, len0) -= Jtr.segment(p0, len0);
    for (const auto& [p1, h1, len1] : blocks) {
      H.block(h0, h1, len0, len1) += JtJ.block(p0, p1, len0, len1);
    }
  }
}

/// The IMU factor between keyframe slots `slot` and slot + 1 at the current estimate.
struct ImuTerm {
  int slot = 0;
  Eigen::Matrix<double, 15, 15> info;  ///< the preintegration's information
  Eigen::Matrix<double, 15, 1> r;
  Eigen::Matrix<double, 15, 30> J;  ///< on both keyframes' states
};

/// IMU factors between consecutive keyframes: their cost 1/2 rᵀ W r, and with `terms` their
/// residuals and Jacobians (appended).
double imu_factors(const Window& window, std::vector<ImuTerm>* terms) {
  if (window.state_dim != 15) return 0;
  double cost = 0;
  for (std::size_t k = 1; k < window.keyframes.size(); ++k) {
    const KeyframeState& i = window.keyframes[k - 1];
    const KeyframeState& j = window.keyframes[k];
    if (!j.imu_from_previous) continue;
    const Eigen::Matrix<double, 15, 15> info = imu_information(*j.imu_from_previous);
    if (terms == nullptr) {
      const Eigen::Matrix<double, 15, 1> r =
          imu_residual(*j.imu_from_previous, i, j, window.gravity);
      cost += 0.5 * r.dot(info * r);
      continue;
    }
    ImuTerm& f = terms->emplace_back();
    f.slot = static_cast<int>(k - 1);
    f.info = info;
    linearize_imu(*j.imu_from_previous, i, j, window.gravity, f.r, f.J);
    cost += 0.5 * f.r.dot(f.info * f.r);
  }
  return cost;
}

/// Adds each IMU factor's JᵀWJ and -JᵀWr to (H, b).
void add_imu_products(const std::vector<ImuTerm>& terms, Eigen::MatrixXd& H, Eigen::VectorXd& b) {
  for (const ImuTerm& f : terms) {
    const Eigen::Matrix<double, 30, 30> JtWJ = f.J.transpose() * f.info * f.J;
    const Eigen::Matrix<double, 30, 1> JtWr = f.J.transpose() * f.info * f.r;
    const int a = f.slot * 15;
    H.block<15, 15>(a, a) += JtWJ.block<15, 15>(0, 0);
    H.block<15, 15>(a, a + 15) += JtWJ.block<15, 15>(0, 15);
    H.block<15, 15>(a + 15, a) += JtWJ.block<15, 15>(15, 0);
    H.block<15, 15>(a + 15, a + 15) += JtWJ.block<15, 15>(15, 15);
    b.segment<30>(a) -= JtWr;
  }
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

/// One inlier observation's reprojection term at the current estimate and its Huber weight.
struct ObservationTerm {
  ReprojectionTerm t;
  RobustWeight w;
  int target = -1;  ///< the observing keyframe's slot; -1 in the anchor itself (same_frame)
};

/// The window's residuals and Jacobians at the current estimate (kernel "linearization"), from
/// which the normal equations are formed (kernel "normal_equations").
struct Linearization {
  struct LandmarkTerms {
    Landmark* landmark = nullptr;
    std::size_t begin = 0, end = 0;  ///< its terms
  };
  std::vector<ObservationTerm> terms;
  std::vector<LandmarkTerms> landmarks;
  std::vector<ImuTerm> imu;
  Eigen::VectorXd prior_r;  ///< the prior's residual (empty without a prior)
  double cost = 0;          ///< robust reprojection + IMU + prior + offset prior
};

/// Fills `lin` (its buffers reused across the LM iterations: a window's terms are about 1.5 MB).
void linearize(Window& window, const SlamOptions& options, Linearization& lin) {
  lin.terms.clear();
  lin.landmarks.clear();
  lin.imu.clear();
  lin.prior_r.resize(0);
  lin.cost = 0;
  ObservationTerm term;
  for (auto& [id, landmark] : window.landmarks) {
    if (!usable(window, landmark)) continue;
    Linearization::LandmarkTerms terms{&landmark, lin.terms.size(), 0};
    for (const Observation& o : landmark.observations) {
      if (!o.inlier || !linearize_reprojection(window, landmark, o, options.pixel_sigma, term.t)) {
        continue;
      }
      term.w = huber(term.t.r.norm(), options.huber_threshold);
      lin.cost += term.w.cost;
      term.target = term.t.same_frame ? -1 : window.slot(o.keyframe_id);
      lin.terms.push_back(term);
    }
    terms.end = lin.terms.size();
    lin.landmarks.push_back(terms);
  }
  lin.cost += imu_factors(window, &lin.imu);
  lin.cost += prior_residual(window, &lin.prior_r);
  lin.cost += add_offset_prior(window, options, nullptr, nullptr);
}

/// How many of each product the normal equations took (their ops, record_normal_equation_ops).
struct ProductCounts {
  std::int64_t observations = 0;  ///< N: reprojection terms
  std::int64_t offset = 0;        ///< O: of them with a disparity-offset Jacobian
  std::int64_t cross = 0;         ///< X: of them in another keyframe than the anchor
  std::int64_t cross_offset = 0;  ///< of those with an offset Jacobian
};

/// H = Σ JᵀWJ, b = -Σ JᵀWr over the terms (Huber weights w), landmark by landmark: per term the
/// scalars H_ll += w J_ρᵀJ_ρ, b_l -= w J_ρᵀr (and with an offset Jacobian J_o: H_lo, H_oo, b_o);
/// per term in keyframe j ≠ anchor a the 6x6 blocks H_aa, H_aj, H_ja, H_jj, the gradients b_a,
/// b_j and the couplings H_la, H_lj (and H_ao, H_jo); then the IMU factors and the priors.
NormalEquations form_normal_equations(const Window& window, const SlamOptions& options,
                                      const Linearization& lin, ProductCounts& counts) {
  const int d = window.state_dim;
  const int off = offset_index(window, options);
  const int C = static_cast<int>(window.keyframes.size()) * d + (off >= 0 ? 1 : 0);
  NormalEquations ne;
  ne.H_cc = Eigen::MatrixXd::Zero(C, C);
  ne.b_c = Eigen::VectorXd::Zero(C);
  ne.cost = lin.cost;
  for (const Linearization::LandmarkTerms& terms : lin.landmarks) {
    LandmarkRow row;
    row.landmark = terms.landmark;
    const int a = window.slot(terms.landmark->anchor_id);
    for (std::size_t i = terms.begin; i < terms.end; ++i) {
      const ReprojectionTerm& t = lin.terms[i].t;
      const RobustWeight& w = lin.terms[i].w;
      ++ne.observations;
      // Rows past t.dim are zero in r and every Jacobian, so the full 4-row blocks are used.
      const Eigen::Vector4d& r = t.r;
      const Eigen::Vector4d& J_rho = t.J_rho;
      row.H_ll += w.weight * J_rho.squaredNorm();
      row.b_l -= w.weight * J_rho.dot(r);
      const Eigen::Vector4d& J_o = t.J_offset;
      const bool has_offset = off >= 0 && J_o.squaredNorm() > 0;
      if (has_offset) {
        ++counts.offset;
        row.H_lo += w.weight * J_rho.dot(J_o);
        ne.H_cc(off, off) += w.weight * J_o.squaredNorm();
        ne.b_c(off) -= w.weight * J_o.dot(r);
      }
      if (t.same_frame) continue;
      ++counts.cross;
      const int j = lin.terms[i].target;
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
        ++counts.cross_offset;
        const Vector6d ha = w.weight * Ja.transpose() * J_o, hj = w.weight * Jj.transpose() * J_o;
        ne.H_cc.block<6, 1>(a * d, off) += ha;
        ne.H_cc.block<1, 6>(off, a * d) += ha.transpose();
        ne.H_cc.block<6, 1>(j * d, off) += hj;
        ne.H_cc.block<1, 6>(off, j * d) += hj.transpose();
      }
    }
    if (row.H_ll > 0) ne.rows.push_back(std::move(row));
  }
  counts.observations = ne.observations;
  add_imu_products(lin.imu, ne.H_cc, ne.b_c);
  add_prior_products(window, options, lin.prior_r, ne.H_cc, ne.b_c);
  add_offset_prior(window, options, &ne.H_cc, &ne.b_c);
  return ne;
}

/// The normal equations' products as the matrix ops the host computes them in (docs/TRACE.md),
/// one batch per shape: per term J_ρᵀJ_ρ and J_ρᵀr (gemm 1 x 1 x 4, 2N), with an offset
/// Jacobian J_ρᵀJ_o, J_oᵀJ_o, J_oᵀr (3O); per cross term JaᵀJa, JjᵀJj (syrk 6 x 6 of 4, 2X),
/// JaᵀJj, JjᵀJa (gemm 6 x 6 x 4, 2X), the gradients and couplings Jᵀr, JᵀJ_ρ (gemm 6 x 1 x 4,
/// 4X) and JᵀJ_o (2 per cross term with an offset); per IMU factor JᵀW (gemm 30 x 15 x 15),
/// JᵀWJ (gemm 30 x 30 x 15, symmetric) and JᵀWr (gemm 30 x 1 x 15); the prior's JᵀJ (syrk) and
/// Jᵀr (gemm).
void record_normal_equation_ops(KernelRecorder& recorder, const ProductCounts& c,
                                const Linearization& lin, const Window& window) {
  namespace f = trace::op_flags;
  using trace::Op;
  const auto describe = [&](Op op, std::int64_t m, std::int64_t n, std::int64_t k,
                            std::uint32_t flags, std::int64_t batch) {
    if (batch > 0) recorder.describe(op, m, n, k, flags, batch);
  };
  describe(Op::Gemm, 1, 1, 4, f::kTransposeA, 2 * c.observations + 3 * c.offset);
  describe(Op::Syrk, 6, 6, 4, f::kSymmetric, 2 * c.cross);
  describe(Op::Gemm, 6, 6, 4, f::kTransposeA, 2 * c.cross);
  describe(Op::Gemm, 6, 1, 4, f::kTransposeA, 4 * c.cross + 2 * c.cross_offset);
  const auto imu = static_cast<std::int64_t>(lin.imu.size());
  describe(Op::Gemm, 30, 15, 15, f::kTransposeA | f::kSymmetric, imu);
  describe(Op::Gemm, 30, 30, 15, f::kSymmetric, imu);
  describe(Op::Gemm, 30, 1, 15, 0, imu);
  if (!window.prior.empty()) {
    const std::int64_t rows = window.prior.J.rows(), cols = window.prior.J.cols();
    describe(Op::Syrk, cols, cols, rows, f::kSymmetric, 1);
    describe(Op::Gemm, cols, 1, rows, f::kTransposeA, 1);
  }
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
  return cost + imu_factors(window, nullptr) + prior_residual(window, nullptr) +
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
  kernel.detail_json = "{\"coupling_blocks\":" + std::to_string(coupling_blocks(ne)) + "}";
}

LmReport optimize_window(Window& window, const SlamOptions& options, KernelRecorder& recorder) {
  LmReport report;
  const int d = window.state_dim;
  const int K = static_cast<int>(window.keyframes.size());
  const int off = offset_index(window, options);
  const int C = K * d + (off >= 0 ? 1 : 0);
  double lambda = options.lm_initial_lambda, nu = 2.0;
  bool relinearize = true;
  Linearization lin;
  NormalEquations ne;
  for (int it = 0; it < options.lm_max_iterations; ++it) {
    if (relinearize) {
      {
        auto k = recorder.kernel("linearization");
        linearize(window, options, lin);
        k.record().m = static_cast<std::int64_t>(lin.terms.size());
        k.record().n = static_cast<std::int64_t>(lin.landmarks.size()) + C;
      }
      auto k = recorder.kernel("normal_equations");
      ProductCounts counts;
      ne = form_normal_equations(window, options, lin, counts);
      record_normal_equation_ops(recorder, counts, lin, window);
      k.record().m = ne.observations;
      k.record().n = C;
      k.record().k = counts.cross;
      k.record().detail_json = nlohmann::json{
          {"landmarks", ne.rows.size()},
          {"coupling_blocks", coupling_blocks(ne)},
          {"imu_factors", lin.imu.size()},
          {"prior_rows", window.prior.J.rows()},
          {"prior_cols",
           window.prior.J.cols()}}.dump();
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
      // Its ops: S = LDLᵀ (ldlt C), the two triangular solves (trsv C, two), and per landmark
      // the couplings' dot products with dx_c (gemm 1 x 1 x 6 a block).
      namespace f = trace::op_flags;
      const std::size_t blocks = coupling_blocks(ne);
      recorder.describe(trace::Op::Ldlt, C, C, 0, f::kSymmetric);
      recorder.describe(trace::Op::Trsv, C, 1, 0, f::kLower, 2);
      if (blocks > 0) {
        recorder.describe(trace::Op::Gemm, 1, 1, 6, f::kTransposeA,
                          static_cast<std::int64_t>(blocks));
      }
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
