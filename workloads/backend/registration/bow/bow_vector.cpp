#include "workloads/backend/registration/bow/bow_vector.hpp"

#include <algorithm>
#include <cmath>

namespace edx::bow {

double l1_norm(const BowVector& v) {
  double sum = 0;
  for (const auto& [word, weight] : v) sum += std::abs(weight);
  return sum;
}

BowVector l1_normalized(const BowVector& v) {
  const double norm = l1_norm(v);
  if (norm == 0) return v;
  BowVector out;
  for (const auto& [word, weight] : v) out.emplace_hint(out.end(), word, weight / norm);
  return out;
}

double l1_score(const BowVector& v, const BowVector& w) {
  const double nv = l1_norm(v), nw = l1_norm(w);
  if (nv == 0 || nw == 0) return 0;
  double sum = 0;
  auto a = v.begin();
  auto b = w.begin();
  while (a != v.end() && b != w.end()) {  // merge walk over the sorted word ids
    if (a->first < b->first) {
      ++a;
    } else if (b->first < a->first) {
      ++b;
    } else {
      const double x = a->second / nv, y = b->second / nw;
      sum += std::abs(x) + std::abs(y) - std::abs(x - y);
      ++a;
      ++b;
    }
  }
  return std::clamp(0.5 * sum, 0.0, 1.0);
}

}  // namespace edx::bow
