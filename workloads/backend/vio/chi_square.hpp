#pragma once
// Chi-square distribution with an integer number of degrees of freedom k, for the gating of
// measurements and the consistency (NEES) bounds.
//   survival Q(x; k) = P(X > x), y = x/2:
//     k = 2m:     Q = sum_{i=0}^{m-1} exp(-y) y^i / i!
//     k = 2m + 1: Q = erfc(sqrt(y)) + sum_{i=1}^{m} exp(-y) y^(i-1/2) / Gamma(i + 1/2)
//   (terms evaluated in logarithms so that large k does not underflow); the quantile is found by
//   bisection on Q.
namespace edx::backend::vio {

/// P(X > x) for X ~ chi-square with `dof` >= 1 degrees of freedom.
double chi2_survival(double x, int dof);
/// x with P(X <= x) = p, 0 < p < 1.
double chi2_quantile(double p, int dof);

}  // namespace edx::backend::vio
