#pragma once
// Least-squares polynomial models of a kernel's host time in one size feature (paper Sec. VI-B:
// projection time linear in the map points, Kalman-gain time quadratic in H's height,
// marginalization time quadratic in the feature count), and their coefficient of determination.
#include <cstddef>
#include <nlohmann/json.hpp>
#include <vector>

namespace edx::arch {

struct PolynomialModel {
  int degree = 1;
  std::vector<double> coefficients;  ///< c0 + c1 x + c2 x² + ...
  std::size_t samples = 0;
  /// R² = 1 − Σ(y − ŷ)² / Σ(y − ȳ)² on the samples it was fitted to (1 when every y is equal
  /// and predicted exactly).
  double r_squared = 0;

  double predict(double x) const;
  nlohmann::json to_json() const;
};

/// Fits y ≈ Σ_j c_j x^j (j = 0..degree) by least squares (Eigen's column-pivoting QR on the
/// Vandermonde matrix, x scaled to [0, 1] for conditioning). Throws std::runtime_error when there
/// are fewer samples than coefficients, the sizes differ, or a value is not finite.
PolynomialModel fit_polynomial(const std::vector<double>& x, const std::vector<double>& y,
                               int degree);

/// R² of a model on other samples (e.g. the frames it was not trained on).
double r_squared(const PolynomialModel& model, const std::vector<double>& x,
                 const std::vector<double>& y);

}  // namespace edx::arch
