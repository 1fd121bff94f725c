#include "workloads/backend/vio/chi_square.hpp"

#include <cmath>
#include <stdexcept>

namespace edx::backend::vio {

double chi2_survival(double x, int dof) {
  if (dof < 1) throw std::invalid_argument("chi2_survival: dof must be >= 1");
  if (x <= 0) return 1.0;
  const double y = 0.5 * x;
  const double log_y = std::log(y);
  double q = 0;
  if (dof % 2 == 0) {
    for (int i = 0; i < dof / 2; ++i) q += std::exp(-y + i * log_y - std::lgamma(i + 1.0));
  } else {
    q = std::erfc(std::sqrt(y));
    for (int i = 1; i <= dof / 2; ++i) q += std::exp(-y + (i - 0.5) * log_y - std::lgamma(i + 0.5));
  }
  return std::min(1.0, q);
}

double chi2_quantile(double p, int dof) {
  if (!(p > 0 && p < 1)) throw std::invalid_argument("chi2_quantile: p must lie in (0, 1)");
  double lo = 0, hi = dof + 20.0 * std::sqrt(2.0 * dof) + 50.0;
  for (int it = 0; it < 200 && hi - lo > 1e-12 * hi; ++it) {
    const double mid = 0.5 * (lo + hi);
    if (1.0 - chi2_survival(mid, dof) < p)
      lo = mid;
    else
      hi = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace edx::backend::vio
