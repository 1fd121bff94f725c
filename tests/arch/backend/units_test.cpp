// The backend units' descriptors (arch/backend/units): every op has a unit, and Table II's use of
// each building block follows from the kernels' ops.
#include "arch/backend/units.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace edx::arch {
namespace {

using trace::Op;

TEST(BackendUnits, EveryOpIsServedByExactlyOneUnit) {
  for (Op op : {Op::Gemm, Op::Syrk, Op::Potrf, Op::Ldlt, Op::Trsm, Op::Trsv, Op::Transpose,
                Op::Inverse}) {
    int serving = 0;
    for (const BackendUnitDescriptor& u : backend_units()) {
      for (Op served : u.ops) serving += served == op ? 1 : 0;
    }
    EXPECT_EQ(serving, 1) << trace::to_string(op);
  }
  EXPECT_EQ(unit_of(Op::Syrk), BackendUnit::kMultiply);
  EXPECT_EQ(unit_of(Op::Ldlt), BackendUnit::kDecompose);
  EXPECT_EQ(unit_of(Op::Trsv), BackendUnit::kSubstitute);
  for (BackendUnit u : kBackendUnits) EXPECT_EQ(backend_unit(u).unit, u);
  EXPECT_STREQ(to_string(BackendUnit::kTranspose), "transpose");
}

TEST(BackendUnits, TableIIUseFollowsFromTheKernelsOps) {
  // Paper Table II: matrix multiplication in all three kernels, decomposition and substitution
  // in the Kalman gain and marginalization, the inverse in marginalization only, transpose in
  // the Kalman gain and marginalization.
  using Names = std::vector<std::string>;
  EXPECT_EQ(kernels_using(BackendUnit::kMultiply),
            (Names{"projection", "kalman_gain", "marginalization"}));
  EXPECT_EQ(kernels_using(BackendUnit::kDecompose), (Names{"kalman_gain", "marginalization"}));
  EXPECT_EQ(kernels_using(BackendUnit::kInverse), (Names{"marginalization"}));
  EXPECT_EQ(kernels_using(BackendUnit::kTranspose), (Names{"kalman_gain", "marginalization"}));
  EXPECT_EQ(kernels_using(BackendUnit::kSubstitute), (Names{"kalman_gain", "marginalization"}));
}

TEST(BackendUnits, MacLanesOfTheConfiguredSizes) {
  BackendConfig c;
  c.gemm_block = 4;
  c.inverse_lanes = 2;
  c.trsv_lanes = 3;
  EXPECT_DOUBLE_EQ(backend_unit(BackendUnit::kMultiply).mac_lanes(c), 16.0);
  EXPECT_DOUBLE_EQ(backend_unit(BackendUnit::kInverse).mac_lanes(c), 2.0);
  EXPECT_DOUBLE_EQ(backend_unit(BackendUnit::kSubstitute).mac_lanes(c), 3.0);
  EXPECT_DOUBLE_EQ(backend_unit(BackendUnit::kTranspose).mac_lanes(c), 0.0);
  EXPECT_DOUBLE_EQ(backend_unit(BackendUnit::kDecompose).mac_lanes(c), double(c.decomp_lanes()));
}

}  // namespace
}  // namespace edx::arch
