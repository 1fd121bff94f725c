#include "arch/scheduler/regression.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace edx::arch {

double PolynomialModel::predict(double x) const {
  double y = 0, power = 1;
  for (double c : coefficients) {
    y += c * power;
    power *= x;
  }
  return y;
}

nlohmann::json PolynomialModel::to_json() const {
  return {{"degree", degree},
          {"coefficients", coefficients},
          {"samples", samples},
          {"r_squared", r_squared}};
}

double r_squared(const PolynomialModel& model, const std::vector<double>& x,
                 const std::vector<double>& y) {
  if (x.size() != y.size() || x.empty()) return 0.0;
  double mean = 0;
  for (double v : y) mean += v;
  mean /= static_cast<double>(y.size());
  double residual = 0, total = 0, squares = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    residual += std::pow(y[i] - model.predict(x[i]), 2);
    total += std::pow(y[i] - mean, 2);
    squares += y[i] * y[i];
  }
  // Times without variance (equal up to rounding, SD below 1e-9 of their RMS: e.g. modeled host
  // times of invocations of one size) leave R² undefined: 1 for a model that hits them, else 0.
  if (total <= 1e-18 * squares) return residual <= 1e-18 * squares ? 1.0 : 0.0;
  return 1.0 - residual / total;
}

PolynomialModel fit_polynomial(const std::vector<double>& x, const std::vector<double>& y,
                               int degree) {
  if (degree < 0) throw std::runtime_error("regression: degree must be >= 0");
  if (x.size() != y.size()) {
    throw std::runtime_error(fmt::format("regression: {} sizes but {} times", x.size(), y.size()));
  }
  const std::size_t n = x.size();
  const std::size_t terms = static_cast<std::size_t>(degree) + 1;
  if (n < terms) {
    throw std::runtime_error(fmt::format(
        "regression: a degree-{} model needs at least {} samples, got {}", degree, terms, n));
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(x[i]) || !std::isfinite(y[i])) {
      throw std::runtime_error(fmt::format("regression: sample {} is not finite", i));
    }
  }
  // Scale x to [0, 1] so the Vandermonde columns have comparable norms: x = scale · u.
  double scale = 0;
  for (double v : x) scale = std::max(scale, std::abs(v));
  if (scale == 0) scale = 1;
  Eigen::MatrixXd a(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(terms));
  Eigen::VectorXd b(static_cast<Eigen::Index>(n));
  for (std::size_t i = 0; i < n; ++i) {
    double power = 1;
    for (std::size_t j = 0; j < terms; ++j) {
      a(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = power;
      power *= x[i] / scale;
    }
    b(static_cast<Eigen::Index>(i)) = y[i];
  }
  const Eigen::VectorXd u = a.colPivHouseholderQr().solve(b);
  PolynomialModel model;
  model.degree = degree;
  model.samples = n;
  // Back to x: c_j = u_j / scale^j.
  double power = 1;
  for (std::size_t j = 0; j < terms; ++j) {
    model.coefficients.push_back(u(static_cast<Eigen::Index>(j)) / power);
    power *= scale;
  }
  model.r_squared = r_squared(model, x, y);
  return model;
}

}  // namespace edx::arch
