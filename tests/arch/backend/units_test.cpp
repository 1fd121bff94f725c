// The backend matrix units as registered kinds (arch/backend/matrix_unit.hpp, units/): the
// paper's five are registered, every op has one unit in the default backend, Table II's use of
// each building block follows from the kernels' ops, and each kind owns its parameters.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "arch/backend/backend_config.hpp"
#include "arch/backend/op_timing.hpp"
#include "tests/arch/backend/backend_test_support.hpp"

namespace edx::arch {
namespace {

using trace::Op;

TEST(BackendUnits, ThePapersFiveKindsAreRegistered) {
  const auto& registry = ComponentRegistry<MatrixUnit>::instance();
  for (const char* kind :
       {"systolic_array", "decomposition", "inverse", "transpose", "substitution"}) {
    const auto* entry = registry.find(kind);
    ASSERT_NE(entry, nullptr) << kind;
    EXPECT_FALSE(entry->doc.empty());
    EXPECT_EQ(entry->make_default()->kind(), kind);
    EXPECT_FALSE(entry->reference("backend.units.x").empty()) << kind;
  }
  EXPECT_EQ(registry.find("tensor_core"), nullptr);
  EXPECT_THROW(registry.at("tensor_core"), std::runtime_error);
}

TEST(BackendUnits, EveryTableIOpIsServedByExactlyOneUnit) {
  // The paper's units serve every op of its kernels; the MSCKF's Householder QR (beyond the
  // paper) only a householder unit a platform adds.
  const BackendConfig c;
  for (Op op : trace::kOps) {
    int serving = 0;
    for (const MatrixUnitInstance& u : c.units) serving += u.unit->serves(op) ? 1 : 0;
    EXPECT_EQ(serving, op == Op::Qr ? 0 : 1) << trace::to_string(op);
  }
  EXPECT_NO_THROW(c.validate());
}

TEST(BackendUnits, TableIIUseFollowsFromTheKernelsOps) {
  // Paper Table II: matrix multiplication in all three kernels, decomposition and substitution
  // in the Kalman gain and marginalization, the inverse in marginalization only, transpose in
  // the Kalman gain and marginalization.
  using Names = std::vector<std::string>;
  const BackendConfig c;
  const auto using_unit = [&](const std::string& name) {
    return kernels_using(testing::unit_index(c, name), c, paper_offload_set());
  };
  EXPECT_EQ(using_unit("gemm"), (Names{"projection", "kalman_gain", "marginalization"}));
  EXPECT_EQ(using_unit("decomposition"), (Names{"kalman_gain", "marginalization"}));
  EXPECT_EQ(using_unit("inverse"), (Names{"marginalization"}));
  EXPECT_EQ(using_unit("transpose"), (Names{"kalman_gain", "marginalization"}));
  EXPECT_EQ(using_unit("substitution"), (Names{"kalman_gain", "marginalization"}));
}

TEST(BackendUnits, MacLanesOfTheConfiguredSizes) {
  const BackendConfig c = testing::small_config();
  const auto lanes = [&](const std::string& name) {
    return c.units[testing::unit_index(c, name)].unit->mac_lanes();
  };
  EXPECT_DOUBLE_EQ(lanes("gemm"), 16.0);
  EXPECT_DOUBLE_EQ(lanes("decomposition"), 4.0);  // 2 x 2
  EXPECT_DOUBLE_EQ(lanes("inverse"), 2.0);
  EXPECT_DOUBLE_EQ(lanes("substitution"), 2.0);
  EXPECT_DOUBLE_EQ(lanes("transpose"), 0.0);
}

TEST(BackendUnits, AUnitsResourcesFollowItsPrecision) {
  // One 4x4 array: 16 MACs of PG060 operators, 11 + 3 DSP each in double, 3 + 2 in single.
  const auto array = ComponentRegistry<MatrixUnit>::instance().make("systolic_array");
  EXPECT_DOUBLE_EQ(array->resources(cost::Arithmetic::kDouble).dsp, 16 * 14.0);
  EXPECT_DOUBLE_EQ(array->resources(cost::Arithmetic::kSingle).dsp, 16 * 5.0);
}

TEST(BackendUnits, HouseholderQrCyclesAndMacsByHand) {
  // qr 6 x 3 on L = 4 lanes, root + reciprocal 30 + 30 a reflector: per column j, r_j = 6 - j
  // rows, ⌈r_j / 4⌉ + 60 + ⌈2 r_j (2 - j) / 4⌉: (2 + 60 + 6) + (2 + 60 + 3) + (1 + 60 + 0).
  BackendConfig c;
  c.units.push_back(make_matrix_unit("qr", "householder", 2));
  ASSERT_NO_THROW(c.validate());
  const trace::OpRecord qr{Op::Qr, 6, 3, 0, 0, 0};
  EXPECT_EQ(op_cycles(qr, 1, c), 68 + 65 + 61);
  // Two copies, 8 lanes: (1 + 60 + 3) + (1 + 60 + 2) + (1 + 60 + 0).
  EXPECT_EQ(op_cycles(qr, 2, c), 64 + 63 + 61);
  // MACs: 6 + 2·6·2, 5 + 2·5·1, 4 (the norms and the reflections).
  EXPECT_EQ(householder_macs(6, 3), 30 + 15 + 4);
  EXPECT_EQ(op_macs(qr, c), 49);
  // In place: the 6 x 3 matrix, 8-byte scalars.
  EXPECT_EQ(op_spm_bytes(qr, c), 6 * 3 * 8);
}

TEST(BackendUnits, ABatchRunsOnTheCopiesInRoundsOrSharedWhicheverIsShorter) {
  BackendConfig c;
  c.units.push_back(make_matrix_unit("qr", "householder", 2));
  trace::OpRecord qr{Op::Qr, 6, 3, 0, 0, 0, 3};
  // Three instances on two copies: shared, 3 x 188; in rounds, ⌈3/2⌉ x 194 = 388.
  EXPECT_EQ(op_cycles(qr, c), 388);
  EXPECT_EQ(op_cycles(qr, 1, c), 3 * 194);
  EXPECT_EQ(op_macs(qr, c), 3 * 49);
  EXPECT_EQ(op_spm_bytes(qr, c), 6 * 3 * 8);  // one instance at a time
  // A gemm batch on the one 4x4 array of the default backend (tiles not overlapped) is b times
  // the single op: 5 x 4 tiles x (4 + 2 x 4).
  const trace::OpRecord gemm{Op::Gemm, 6, 6, 4, 0, 0};
  trace::OpRecord batch = gemm;
  batch.batch = 5;
  EXPECT_EQ(op_cycles(batch, c), 5 * 4 * (4 + 8));
  EXPECT_EQ(op_macs(batch, c), 5 * 6 * 6 * 4);
  // With overlapped tiles the batch's 5 x 4 tiles stream as one op's: 20 max(4, 4) + 2 x 4.
  testing::set_unit(c, "gemm", "{overlap_tiles: true}");
  EXPECT_EQ(op_cycles(gemm, c), 4 * 4 + 8);
  EXPECT_EQ(op_cycles(batch, c), 20 * 4 + 8);
  batch.batch = 0;
  EXPECT_THROW(op_cycles(batch, c), std::runtime_error);
}

}  // namespace
}  // namespace edx::arch
