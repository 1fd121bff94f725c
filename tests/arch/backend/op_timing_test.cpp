// Cycles of each backend op against hand-computed values (arch/backend/op_timing.hpp).
#include "arch/backend/op_timing.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <stdexcept>
#include <string>

#include "arch/backend/backend_config.hpp"
#include "tests/arch/backend/backend_test_support.hpp"

namespace edx::arch {
namespace {

namespace flags = trace::op_flags;
using testing::small_config;
using trace::Op;
using trace::OpRecord;

OpRecord op(Op kind, std::int64_t m, std::int64_t n, std::int64_t k, std::uint32_t f = 0) {
  return OpRecord{kind, m, n, k, f, 0};
}

TEST(BackendUnits, TableTwoMapping) {
  const BackendConfig c;  // the paper's five units
  const auto served_by = [&](Op o) { return serving_unit(o, c).name; };
  EXPECT_EQ(served_by(Op::Gemm), "gemm");
  EXPECT_EQ(served_by(Op::Syrk), "gemm");
  EXPECT_EQ(served_by(Op::Potrf), "decomposition");
  EXPECT_EQ(served_by(Op::Ldlt), "decomposition");
  EXPECT_EQ(served_by(Op::Inverse), "inverse");
  EXPECT_EQ(served_by(Op::Transpose), "transpose");
  EXPECT_EQ(served_by(Op::Trsm), "substitution");
  EXPECT_EQ(served_by(Op::Trsv), "substitution");
}

TEST(BackendOpCycles, Gemm) {
  const BackendConfig c = small_config();
  // 10x6x7: ⌈10/4⌉ ⌈6/4⌉ = 3 x 2 = 6 tiles of 7 + 8 = 15 cycles.
  EXPECT_EQ(op_cycles(op(Op::Gemm, 10, 6, 7), c), 90);
  // Transposed operands cost nothing.
  EXPECT_EQ(op_cycles(op(Op::Gemm, 10, 6, 7, flags::kTransposeA | flags::kTransposeB), c), 90);
  // Matrix-vector 9x1x5: 3 x 1 tiles of 13.
  EXPECT_EQ(op_cycles(op(Op::Gemm, 9, 1, 5), c), 39);
  EXPECT_EQ(op_cycles(op(Op::Gemm, 0, 6, 7), c), 0);
}

TEST(BackendOpCycles, SymmetricGemmResultComputesUpperTiles) {
  BackendConfig c = small_config();
  // S = H (P H^T), 10x10 of k = 5: 3 tile rows -> 6 upper tiles of 13 cycles.
  EXPECT_EQ(op_cycles(op(Op::Gemm, 10, 10, 5, flags::kSymmetric), c), 78);
  // P H^T (8x10 of 8; P symmetric, the result is not square): all 2 x 3 tiles of 16.
  EXPECT_EQ(op_cycles(op(Op::Gemm, 8, 10, 8, flags::kSymmetric | flags::kTransposeB), c), 96);
  c.symmetric_optimization = false;
  EXPECT_EQ(op_cycles(op(Op::Gemm, 10, 10, 5, flags::kSymmetric), c), 117);  // 9 x 13
}

TEST(BackendOpCycles, SyrkHalvesBlocksExactly) {
  BackendConfig c = small_config();
  // 9x9 of k = 3: 3 tile rows: 6 upper tiles (on) vs 9 (off), 3 + 8 = 11 cycles each.
  EXPECT_EQ(op_cycles(op(Op::Syrk, 9, 9, 3), c), 66);
  c.symmetric_optimization = false;
  EXPECT_EQ(op_cycles(op(Op::Syrk, 9, 9, 3), c), 99);
  // The tile count is that of the blocks (i, j) with i <= j, counted one by one.
  for (const int block : {1, 3, 4, 16}) {
    for (const std::int64_t m : {1, 4, 5, 17, 64, 100, 306}) {
      const std::int64_t tiles = (m + block - 1) / block;
      std::int64_t upper = 0;
      for (std::int64_t i = 0; i < tiles; ++i) {
        for (std::int64_t j = i; j < tiles; ++j) ++upper;
      }
      BackendConfig on = small_config(), off = small_config();
      testing::set_unit(on, "gemm", fmt::format("{{block: {}}}", block));
      testing::set_unit(off, "gemm", fmt::format("{{block: {}}}", block));
      off.symmetric_optimization = false;
      const std::int64_t per_tile = 7 + 2 * block;
      EXPECT_EQ(op_cycles(op(Op::Syrk, m, m, 7), on), upper * per_tile)
          << "m " << m << " b " << block;
      EXPECT_EQ(op_cycles(op(Op::Syrk, m, m, 7), off), tiles * tiles * per_tile);
    }
  }
}

/// Multiply-adds of a textbook right-looking Cholesky, counted by running its loops.
std::int64_t counted_cholesky_macs(std::int64_t n) {
  std::int64_t macs = 0;
  for (std::int64_t j = 0; j < n; ++j) {
    for (std::int64_t i = j + 1; i < n; ++i) ++macs;  // l_ij = a_ij * (1 / l_jj)
    for (std::int64_t i = j + 1; i < n; ++i) {
      for (std::int64_t k = j + 1; k <= i; ++k) ++macs;  // a_ik -= l_ij l_kj
    }
  }
  return macs;
}

TEST(BackendOpCycles, Factorizations) {
  for (const std::int64_t n : {1, 2, 6, 13, 40}) {
    EXPECT_EQ(factorization_macs(n), counted_cholesky_macs(n)) << n;
  }
  const BackendConfig c = small_config();
  // 6x6: (216 - 6)/6 + 15 = 50 MACs on 4 lanes = 13 cycles; + 6 columns x (sqrt 5 + div 10).
  EXPECT_EQ(factorization_macs(6), 50);
  EXPECT_EQ(op_cycles(op(Op::Potrf, 6, 6, 0, flags::kSymmetric), c), 13 + 90);
  // LDL^T: no root: 13 + 6 x 10.
  EXPECT_EQ(op_cycles(op(Op::Ldlt, 6, 6, 0, flags::kSymmetric), c), 13 + 60);
  EXPECT_EQ(op_cycles(op(Op::Potrf, 0, 0, 0), c), 0);
}

TEST(BackendOpCycles, Substitution) {
  const BackendConfig c = small_config();
  // 5x5 triangle, 3 right-hand sides: reciprocals 10 + 4, broadcasts 5, products
  // 3 x 5 x 6 / 2 = 45 on 2 lanes = 23.
  EXPECT_EQ(op_cycles(op(Op::Trsm, 5, 3, 0, flags::kLower), c), 10 + 4 + 5 + 23);
  // trsv: one right-hand side (n is ignored): 15 products -> 8.
  EXPECT_EQ(op_cycles(op(Op::Trsv, 5, 1, 0, flags::kLower), c), 10 + 4 + 5 + 8);
  EXPECT_EQ(op_cycles(op(Op::Trsm, 5, 0, 0), c), 0);
}

TEST(BackendOpCycles, OverlappedTilesPayFillAndDrainOnce) {
  BackendConfig c = small_config(150.0, /*overlap_tiles=*/true);
  // 10x6x7: 6 tiles of max(7, 4) = 7 cycles + one fill/drain of 8.
  EXPECT_EQ(op_cycles(op(Op::Gemm, 10, 6, 7), c), 6 * 7 + 8);
  // k = 2 < b: a tile cannot drain its 4 results a column faster than 4 cycles: 3 x 4 + 8
  // (30 = 3 x (2 + 8) without the overlap).
  EXPECT_EQ(op_cycles(op(Op::Gemm, 3, 9, 2), c), 3 * 4 + 8);
  EXPECT_EQ(op_cycles(op(Op::Syrk, 9, 9, 3), c), 6 * 4 + 8);  // 6 upper tiles
  EXPECT_EQ(op_cycles(op(Op::Gemm, 0, 9, 5), c), 0);
  EXPECT_EQ(op_cycles(op(Op::Gemm, 3, 9, 2), small_config()), 30);
}

TEST(BackendOpCycles, BlockedSubstitutionUpdatesOnTheArray) {
  const BackendConfig c = small_config(150.0, false, /*blocked=*/true);
  // 10x10 triangle, 3 right-hand sides, b = 4: reciprocals 10 + 9 = 19; block 0 (4 rows): solve
  // 4 + ⌈3 x 4 x 5 / 2 / 2⌉ = 19; block 1: update 4x3 of k = 4 (1 tile, 4 + 8) = 12, solve 19;
  // block 2 (2 rows): update 2x3 of k = 8 (1 tile, 16), solve 2 + ⌈9 / 2⌉ = 7.
  EXPECT_EQ(op_cycles(op(Op::Trsm, 10, 3, 0, flags::kLower), c), 19 + 19 + 31 + 23);
  // A triangle within one block costs what the unblocked unit takes: 10 + 3 + 4 + 15.
  EXPECT_EQ(op_cycles(op(Op::Trsm, 4, 3, 0), c), 32);
  const BackendConfig unblocked = small_config();
  EXPECT_EQ(op_cycles(op(Op::Trsm, 4, 3, 0), unblocked), 32);
  EXPECT_EQ(op_cycles(op(Op::Trsm, 10, 3, 0), unblocked), 10 + 9 + 10 + 83);  // ⌈165 / 2⌉
}

TEST(BackendOpCycles, BlockedFactorizationUpdatesOnTheArray) {
  const BackendConfig c = small_config(150.0, false, /*blocked=*/true);
  // potrf 10, b = 4 (per column: root 5 + divide 10):
  //   block 0 (4, 6 below): diagonal ⌈16 / 4⌉ + 4 x 15 = 64; panel 4 + ⌈6 x 10 / 2⌉ = 34;
  //            syrk 6x6 of k = 4: 3 upper tiles x 12 = 36
  //   block 1 (4, 2 below): 64; panel 4 + ⌈2 x 10 / 2⌉ = 14; syrk 2x2: 1 tile, 12
  //   block 2 (2): ⌈2 / 4⌉ + 2 x 15 = 31
  EXPECT_EQ(op_cycles(op(Op::Potrf, 10, 10, 0, flags::kSymmetric), c),
            (64 + 34 + 36) + (64 + 14 + 12) + 31);
  // LDL^T: 10 a column: diagonals 4 + 40 and 1 + 20.
  EXPECT_EQ(op_cycles(op(Op::Ldlt, 10, 10, 0, flags::kSymmetric), c),
            (44 + 34 + 36) + (44 + 14 + 12) + 21);
  // Overlapped tiles: the syrks take 3 x 4 + 8 and 1 x 4 + 8.
  const BackendConfig overlapped = small_config(150.0, /*overlap_tiles=*/true, /*blocked=*/true);
  EXPECT_EQ(op_cycles(op(Op::Potrf, 10, 10, 0), overlapped), (64 + 34 + 20) + (64 + 14 + 12) + 31);
  // One block: the unblocked formula (13 + 90, Factorizations above).
  EXPECT_EQ(op_cycles(op(Op::Potrf, 4, 4, 0), c), 4 + 60);
  EXPECT_EQ(op_cycles(op(Op::Potrf, 4, 4, 0), small_config()), 4 + 60);
}

/// The backend of configs/edx_car.yaml.
BackendConfig car_backend() {
  const std::string path = std::string(EDX_SOURCE_DIR) + "/configs/edx_car.yaml";
  return testing::parse_backend(YAML::LoadFile(path)["backend"], path);
}

TEST(BackendOpCycles, CarKalmanGainSolveBlocked) {
  // The Car's units (b = 4 with overlapped tiles, one substitution lane, divider 30, blocked
  // solvers), on the typical Kalman gain's trsm (66-row triangle, 211 right-hand sides):
  //   reciprocals 30 + 65 = 95; block 0: 4 + 211 x 10 = 2114;
  //   blocks 1..15: update 53 tiles x 4i + 8 and the solve 2114: Σ = 212 x 120 + 15 x 2122;
  //   block 16 (2 rows): update 53 x 64 + 8 = 3400, solve 2 + 211 x 3 = 635.
  BackendConfig c = car_backend();
  EXPECT_EQ(op_cycles(op(Op::Trsm, 66, 211, 0, flags::kLower), c),
            95 + 2114 + 212 * 120 + 15 * 2122 + 3400 + 635);
  // Unblocked: 30 + 65 + 66 + 211 x 66 x 67 / 2 on one lane.
  testing::set_unit(c, "substitution", "{lanes: 1, blocked: false}");
  EXPECT_EQ(op_cycles(op(Op::Trsm, 66, 211, 0, flags::kLower), c), 161 + 466521);
}

TEST(BackendOpCycles, Transpose) {
  const BackendConfig c = small_config();
  EXPECT_EQ(op_cycles(op(Op::Transpose, 7, 5, 0), c), 18);  // ⌈35 / 2⌉
  EXPECT_EQ(op_cycles(op(Op::Transpose, 8, 1, 0), c), 4);
}

TEST(BackendOpCycles, Inverse) {
  BackendConfig c = small_config();
  const std::uint32_t structured = flags::kDiagonalBlock | flags::kBlock6x6 | flags::kSymmetric;
  // General 5x5 Gauss-Jordan: 5 pivots x 10 + ⌈125 / 2⌉.
  EXPECT_EQ(op_cycles(op(Op::Inverse, 5, 5, 0), c), 50 + 63);
  // Structured 10x10 (d = 4): reciprocals 10 + ⌈4/2⌉ = 12; 6x6 Gauss-Jordan 60 + 108 = 168;
  // products 78 x 4 + 6 x sym(4) = 312 + 60 = 372 on 2 lanes = 186.
  EXPECT_EQ(op_cycles(op(Op::Inverse, 10, 10, 0, structured), c), 12 + 168 + 186);
  // Without the 6x6 flag (a 15-dimensional pose block) or with the unit off: general.
  EXPECT_EQ(op_cycles(op(Op::Inverse, 10, 10, 0, flags::kDiagonalBlock), c), 100 + 500);
  testing::set_unit(c, "inverse", "{lanes: 2, divide_latency_cycles: 10, structured: false}");
  EXPECT_EQ(op_cycles(op(Op::Inverse, 10, 10, 0, structured), c), 600);
  c = small_config();
  c.symmetric_optimization = false;  // the dense top-left block in full: 6 x 16 products
  EXPECT_EQ(op_cycles(op(Op::Inverse, 10, 10, 0, structured), c), 12 + 168 + (312 + 96) / 2);
}

TEST(BackendOpCycles, DiagonalInverseIsItsReciprocals) {
  // SLAM's Schur complement inverts the damped H_ll, diagonal: 40 reciprocals on 2 lanes after
  // the divider's 10 cycles; 40 scalars in and out, no multiply-adds.
  const BackendConfig c = small_config();
  const OpRecord d = op(Op::Inverse, 40, 40, 0, flags::kDiagonal | flags::kSymmetric);
  EXPECT_EQ(op_cycles(d, c), 10 + 20);
  EXPECT_EQ(op_spm_bytes(d, c), 80 * 8);
  EXPECT_EQ(op_macs(d, c), 0);
}

TEST(BackendOpCycles, StructuredInverseBeatsGeneralFor100Landmarks) {
  const BackendConfig c;  // defaults
  const std::int64_t m = 3 * 100 + 6;
  const std::uint32_t structured = flags::kDiagonalBlock | flags::kBlock6x6 | flags::kSymmetric;
  const std::int64_t fast = op_cycles(op(Op::Inverse, m, m, 0, structured), c);
  const std::int64_t general = op_cycles(op(Op::Inverse, m, m, 0, flags::kSymmetric), c);
  EXPECT_EQ(general, m * 30 + m * m * m);  // m pivots x t_div + m^3 on one lane
  EXPECT_LT(10 * fast, general);           // n^3 against ~3 n^2: more than an order of magnitude
}

TEST(BackendOpCycles, NegativeDimensionThrows) {
  EXPECT_THROW(op_cycles(op(Op::Gemm, -1, 2, 2), BackendConfig{}), std::runtime_error);
}

TEST(BackendOpSpm, OperandBytes) {
  BackendConfig c = small_config();
  // gemm 10x6x7: A 70 + B 42 + C 60 doubles.
  EXPECT_EQ(op_spm_bytes(op(Op::Gemm, 10, 6, 7), c), 172 * 8);
  // S (10x10 of 5, symmetric): 50 + 50 + sym(10) = 55.
  EXPECT_EQ(op_spm_bytes(op(Op::Gemm, 10, 10, 5, flags::kSymmetric), c), 155 * 8);
  // P H^T (8x10 of 8, P symmetric): sym(8) 36 + 80 + 80.
  EXPECT_EQ(op_spm_bytes(op(Op::Gemm, 8, 10, 8, flags::kSymmetric), c), 196 * 8);
  EXPECT_EQ(op_spm_bytes(op(Op::Syrk, 9, 9, 3), c), (27 + 45) * 8);
  EXPECT_EQ(op_spm_bytes(op(Op::Potrf, 6, 6, 0), c), 21 * 8);
  EXPECT_EQ(op_spm_bytes(op(Op::Trsm, 5, 3, 0), c), (15 + 15) * 8);
  EXPECT_EQ(op_spm_bytes(op(Op::Transpose, 7, 5, 0), c), 70 * 8);
  // Structured 10x10: diagonal 4 + B 24 + D sym(6) 21 in, sym(10) 55 out.
  const std::uint32_t structured = flags::kDiagonalBlock | flags::kBlock6x6 | flags::kSymmetric;
  EXPECT_EQ(op_spm_bytes(op(Op::Inverse, 10, 10, 0, structured), c), 104 * 8);
  c.symmetric_optimization = false;
  EXPECT_EQ(op_spm_bytes(op(Op::Gemm, 10, 10, 5, flags::kSymmetric), c), 200 * 8);
  EXPECT_EQ(op_spm_bytes(op(Op::Inverse, 5, 5, 0, flags::kSymmetric), c), 50 * 8);
}

TEST(BackendConfigYaml, ReadsFieldsAndNamesFileLineKey) {
  const BackendConfig c = testing::parse_backend(
      YAML::Load("clock_mhz: 200\nsymmetric_optimization: false\nspm_bytes: 4194304\n"
                 "units:\n  gemm: {block: 32, overlap_tiles: true}\n  inverse: {count: 0}\n"
                 "  substitution: {count: 0}\n"
                 "  solver: {kind: substitution, lanes: 3, blocked: true, count: 2}\n"),
      "car.yaml");
  EXPECT_DOUBLE_EQ(c.clock_mhz, 200.0);
  EXPECT_FALSE(c.symmetric_optimization);
  EXPECT_EQ(c.spm_bytes, 4194304);
  // The five defaults in their order (gemm overridden, its kind kept), then the new one.
  ASSERT_EQ(c.units.size(), 6u);
  EXPECT_EQ(c.units[0].name, "gemm");
  EXPECT_EQ(c.units[0].unit->kind(), "systolic_array");
  EXPECT_EQ(c.units[0].unit->tile(), 32);
  EXPECT_EQ(c.units[5].name, "solver");
  EXPECT_EQ(c.units[5].count, 2);
  EXPECT_DOUBLE_EQ(c.units[5].unit->mac_lanes(), 3.0);
  EXPECT_EQ(c.unit_for(Op::Trsm), &c.units[5]);
  EXPECT_EQ(c.to_json()["units"]["gemm"]["block"], 32);
  EXPECT_EQ(c.to_json()["units"]["gemm"]["overlap_tiles"], true);
  EXPECT_EQ(c.to_json()["units"]["solver"]["kind"], "substitution");
  EXPECT_EQ(c.unit_for(Op::Inverse), nullptr);  // no inverse unit: inverses stay on the host
  EXPECT_EQ(BackendConfig{}.units.size(), 5u);  // without units: Table II's five

  const auto error_of = [](const std::string& text) {
    try {
      testing::parse_backend(YAML::Load(text), "car.yaml");
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const auto expect_error = [&](const std::string& text, const std::string& part) {
    EXPECT_NE(error_of(text).find(part), std::string::npos) << error_of(text);
  };
  expect_error("clock_mhz: 200\nunits:\n  gemm: {kind: systolic_array, block: 0}\n",
               "car.yaml:3: backend.units.gemm.block: expected an integer in [1, 256], got '0'");
  expect_error("units:\n  gemm:\n    kind: systolic_array\n    blok: 4\n",
               "car.yaml:4: backend.units.gemm.blok: unknown key");
  expect_error(
      "units:\n  gemm:\n    kind: tensor_core\n",
      "car.yaml:3: backend.units.gemm.kind: expected one of decomposition, householder, inverse, ");
  expect_error("units:\n  array2: {block: 4}\n",
               "backend.units.array2.kind: required for a unit not among the defaults");
  expect_error("units:\n  t2: {kind: transpose}\n",
               "car.yaml:2: backend.units.t2: expected one unit per op, but transpose serves "
               "transpose too (count: 0 leaves a unit out)");
  // A value the reader accepts but validate() refuses still names its line.
  expect_error("clock_mhz: 100\n\nprecision: fp16\n", "car.yaml:3: backend.precision");
  // The element size became the precision.
  expect_error("scalar_bytes: 4\n",
               "car.yaml:1: backend.scalar_bytes: moved: now backend.precision (fp64: 8 bytes a "
               "scalar, fp32: 4)");
  // One precision for the whole backend: a unit has none of its own.
  expect_error("units: {gemm: {precision: double}}\n", "backend.units.gemm.precision");
  // The keys of the fixed five-unit backend name where they went.
  expect_error("gemm_block: 4\n",
               "car.yaml:1: backend.gemm_block: moved: now backend.units.<name>.block of a "
               "systolic_array unit");
}

TEST(BackendConfigYaml, EveryUnitComputesAtTheBackendsPrecision) {
  const BackendConfig single = testing::parse_backend(
      YAML::Load("precision: fp32\nunits: {gemm: {block: 2}, householder: {kind: householder}}\n"),
      "x.yaml");
  EXPECT_EQ(single.scalar_bytes(), 4);
  for (const MatrixUnitInstance& u : single.units) {  // listed, default and added units alike
    EXPECT_EQ(u.arithmetic(), cost::Arithmetic::kSingle) << u.name;
  }
  EXPECT_EQ(single.matrix_format().scalar_bytes, 4);
  EXPECT_EQ(BackendConfig{}.scalar_bytes(), 8);
  EXPECT_EQ(BackendConfig{}.units[0].arithmetic(), cost::Arithmetic::kDouble);
}

TEST(BackendOpCycles, CopiesShareAnOpsWork) {
  BackendConfig c = small_config();
  // gemm 10x6x7 on two arrays: 6 tiles dealt out, 3 each, of 15 cycles.
  EXPECT_EQ(op_cycles(op(Op::Gemm, 10, 6, 7), 2, c), 45);
  EXPECT_EQ(op_cycles(op(Op::Gemm, 10, 6, 7), 4, c), 30);  // ⌈6/4⌉ = 2 tiles
  // potrf 6 on two decomposition units: 50 MACs on 8 lanes = 7, the column chain unchanged.
  EXPECT_EQ(op_cycles(op(Op::Potrf, 6, 6, 0), 2, c), 7 + 90);
  // transpose 7x5 on two: ⌈35/4⌉.
  EXPECT_EQ(op_cycles(op(Op::Transpose, 7, 5, 0), 2, c), 9);
  // The instance's count is what op_cycles uses by default.
  c.units[testing::unit_index(c, "gemm")].count = 2;
  EXPECT_EQ(op_cycles(op(Op::Gemm, 10, 6, 7), c), 45);
  // Count 0 leaves the unit out: nobody serves gemm.
  c.units[testing::unit_index(c, "gemm")].count = 0;
  EXPECT_EQ(c.unit_for(Op::Gemm), nullptr);
  EXPECT_THROW(op_cycles(op(Op::Gemm, 10, 6, 7), c), std::runtime_error);
}

}  // namespace
}  // namespace edx::arch
