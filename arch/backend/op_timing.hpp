#pragma once
// Cycles of each matrix op of the trace (docs/TRACE.md, ops table) on the backend accelerator's
// units (paper Sec. VI-A, Table II), and the scratchpad bytes its operands take. These are the
// "latency profiles of the five building blocks" the runtime scheduler estimates accelerator
// time from (Sec. VI-B): a scheduler calls op_cycles() per op, or kernel_cycles() per kernel.
// Every formula is listed in docs/MODEL.md ("Backend accelerator"); ceil(x / y) is written ⌈x/y⌉.
//
// Which unit serves each op (Table II's building blocks):
//   gemm, syrk        -> matrix multiplication     potrf, ldlt  -> decomposition
//   inverse           -> inverse                    transpose    -> transpose
//   trsm, trsv        -> forward/back substitution
//
// Symmetric matrices (op flag kSymmetric, "result or operand is symmetric"): a syrk's result is
// symmetric; for a gemm the flag is read as: the result when it is square (m == n: S = H P H^T,
// the SLAM prior H* = A_rr - A_rm A_mm^-1 A_mr), else the square operand (A when m == k: P in
// P H^T; B when k == n: A_mm^-1 in A_rm A_mm^-1). With symmetric_optimization a symmetric result
// is computed as its blocks on and above the diagonal, and any symmetric matrix is stored as a
// triangle, sym(n) = n(n+1)/2 scalars (else n^2).
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "arch/backend/backend_config.hpp"
#include "arch/backend/units.hpp"
#include "arch/kernels/kernels.hpp"
#include "workloads/trace/records.hpp"

namespace edx::arch {

/// ⌈a / b⌉ for a >= 0, b >= 1.
std::int64_t ceil_div(std::int64_t a, std::int64_t b);
/// Tiles of a ⌈m/b⌉ x ⌈n/b⌉ result on a b x b array; when `symmetric_result` (m == n) only the
/// T(T+1)/2 tiles on and above the diagonal, T = ⌈m/b⌉.
std::int64_t gemm_tiles(std::int64_t m, std::int64_t n, int block, bool symmetric_result);

/// Multiply-adds of an unblocked n x n Cholesky or LDL^T (right-looking): the trailing updates
/// Σ_{j<n} (n-j-1)(n-j)/2 = (n^3 - n)/6 plus the column scalings by the pivot's reciprocal
/// Σ_{j<n} (n-j-1) = n(n-1)/2. (LDL^T updates a_ik -= l_ij a_kj with the unscaled a_kj, so it
/// needs no more products than Cholesky.)
std::int64_t factorization_macs(std::int64_t n);

/// Cycles of a general n x n Gauss-Jordan inverse on `lanes` MAC lanes: each of the n pivot
/// steps takes a reciprocal (divide latency on the critical path) and updates n rows of n
/// (n^2 products): n * t_div + ⌈n^3 / lanes⌉.
std::int64_t general_inverse_cycles(std::int64_t n, const BackendConfig& config);

/// Cycles of the structured inverse of A_mm = [A B; B^T D], A diagonal (d = m - 6), D 6x6, as
/// the SLAM marginalization computes it (workloads/backend/slam/marginalizer.cpp), producing the
/// full symmetric inverse:
///   reciprocals a^-1 of the diagonal, pipelined over the lanes   t_div + ⌈d / L⌉
///   S^-1 of the 6x6 Schur complement, Gauss-Jordan               general_inverse_cycles(6)
///   products on the lanes: A^-1 B (6d), S = D - B^T A^-1 B (36d), A^-1 B S^-1 (36d), and the
///   dense top-left block (A^-1 B S^-1)(A^-1 B)^T + A^-1 (6 sym(d) with the symmetric
///   optimization, else 6 d^2)                                     ⌈(78d + 6 sym(d)) / L⌉
std::int64_t structured_inverse_cycles(std::int64_t m, const BackendConfig& config);

/// Cycles of `tiles` output tiles of a b x b array accumulating k products each: tiles (k + 2b)
/// (fill and drain per tile), or with gemm_overlap_tiles tiles max(k, b) + 2b (the next tile
/// streams in while the previous one drains; a tile cannot drain faster than its b results a
/// column take to shift out). 0 when tiles or k is 0.
std::int64_t array_cycles(std::int64_t tiles, std::int64_t k, const BackendConfig& config);

/// blocked_solvers: an m x m triangle against `rhs` right-hand sides in blocks of b rows
/// (b = gemm_block, s_i = min(b, m - i b)): the reciprocals of the whole diagonal once
/// (t_div + m - 1, pipelined), then per block row the update B_i -= L_i,<i X_<i on the array
/// (array_cycles(tiles(s_i, rhs), i b), none for the first) and the s_i x s_i solve on the
/// substitution unit (s_i + ⌈rhs s_i (s_i+1)/2 / L_s⌉). With m <= b it equals the unblocked
/// formula of op_cycles.
std::int64_t blocked_substitution_cycles(std::int64_t m, std::int64_t rhs,
                                         const BackendConfig& config);

/// blocked_solvers: right-looking blocked Cholesky / LDL^T of m in blocks of b = gemm_block; per
/// diagonal block j (size s, `rest` rows below it): the block on the decomposition unit
/// (⌈factorization_macs(s) / b_d^2⌉ + s per_column), the panel on the substitution unit
/// (s + ⌈rest s (s+1)/2 / L_s⌉) and the trailing syrk on the array (array_cycles of the
/// rest x rest result's tiles, symmetric with symmetric_optimization, k = s). per_column: t_sqrt
/// + t_div (potrf) or t_div (ldlt). With m <= b it equals the unblocked formula.
std::int64_t blocked_factorization_cycles(std::int64_t m, std::int64_t per_column,
                                          const BackendConfig& config);

/// True when `op` is an inverse the structured unit serves: flags kDiagonalBlock and kBlock6x6,
/// m > 6, and structured_inverse on.
bool uses_structured_inverse(const trace::OpRecord& op, const BackendConfig& config);

/// Cycles of one op on its unit (0 for an op with a zero dimension):
///   gemm  m x n x k on the b x b array: array_cycles(tiles(m, n), k) = tiles(m, n) * (k + 2b),
///         the 2b being the array's fill and drain per tile (operands skewed into b rows and
///         columns, results shifted out), or tiles max(k, b) + 2b with gemm_overlap_tiles;
///         transposed operands (flags kTransposeA/B) cost nothing (the address generator reads
///         them transposed); a symmetric result counts only the upper tiles (see above)
///   syrk  m x m result of k: the same with n = m, the result always symmetric
///   potrf ⌈factorization_macs(m) / b_d^2⌉ + m (t_sqrt + t_div)    (a root and a reciprocal
///         per column on the critical path)
///   ldlt  ⌈factorization_macs(m) / b_d^2⌉ + m t_div               (a reciprocal per column)
///         (with blocked_solvers: blocked_factorization_cycles)
///   trsm, trsv  column-oriented substitution of an m x m triangle against n right-hand sides:
///         reciprocals of the diagonal (t_div + m - 1, pipelined), one broadcast cycle per
///         column, and the n m(m+1)/2 products on the lanes:
///         t_div + (m - 1) + m + ⌈n m (m+1)/2 / L_s⌉   (trsv: n = 1)
///         (with blocked_solvers: blocked_substitution_cycles)
///   transpose  ⌈m n / w⌉
///   inverse  structured_inverse_cycles(m) when uses_structured_inverse, else
///         general_inverse_cycles(m)
/// Throws std::runtime_error for negative dimensions.
std::int64_t op_cycles(const trace::OpRecord& op, const BackendConfig& config);

/// Scratchpad bytes of one op's operands and result (Sec. VI-A: "the input matrices must be
/// ready before an operation starts"), s bytes a scalar, sym(n) = n(n+1)/2 with the symmetric
/// optimization, else n^2:
///   gemm  (mk + kn + mn) s, the symmetric one of them counted as sym        syrk (mk + sym(m)) s
///   potrf, ldlt  sym(m) s (in place)          trsm, trsv  (sym(m) + mn) s (triangle; in place)
///   transpose  2mn s (out of place)
///   inverse  structured: in d + 6d + sym(6) (diagonal, B, D), out sym(m); general: 2 m^2, or
///            2 sym(m) when kSymmetric
std::int64_t op_spm_bytes(const trace::OpRecord& op, const BackendConfig& config);

/// Scalars an op reads (its operands) and writes (its result) at least once, stored as
/// op_spm_bytes stores them (sym(n) for a symmetric matrix with the optimization):
///   gemm  in mk + kn, out mn          syrk  in mk, out sym(m)
///   potrf, ldlt  in sym(m), out sym(m)       trsm, trsv  in sym(m) + m·rhs, out m·rhs
///   transpose  in mn, out mn
///   inverse  structured: in d + 6d + sym(6), out sym(m); general: in m^2, out m^2 (sym(m) each
///            when kSymmetric)
struct OperandScalars {
  std::int64_t in = 0, out = 0;
};
OperandScalars op_operand_scalars(const trace::OpRecord& op, const BackendConfig& config);

/// Multiply-adds W of one op, the work a tiled out-of-core algorithm re-reads operands for:
///   gemm mnk (k sym(m) for a symmetric result with the optimization)   syrk k sym(m)
///   potrf, ldlt factorization_macs(m)     trsm, trsv rhs m(m+1)/2      transpose 0
///   inverse: general m^3, structured 78d + 6 sym(d) (its products, structured_inverse_cycles)
std::int64_t op_macs(const trace::OpRecord& op, const BackendConfig& config);

/// SPM tile side of an op that spills: t = max(1, ⌊√(M / 3)⌋), M = spm_bytes / s the SPM's
/// capacity in scalars: three t x t tiles (two operand tiles and the resident accumulator) fill
/// it (the tiled matrix multiply; Lam, Rothberg and Wolf, ASPLOS 1991).
std::int64_t spill_tile(const BackendConfig& config);

/// DRAM traffic of one op run out of core (docs/MODEL.md, "SPM spills"); zero when the op fits
/// the SPM (op_spm_bytes <= spm_bytes). Tiled at t = spill_tile(): each t x t x t block of its W
/// multiply-adds reads two t x t operand tiles while the accumulator tile stays in the SPM, so
/// the op reads 2W / t scalars (every operand at least once) and writes its result once:
///   read  = s · max(in, ⌈2W / t⌉),   write = s · out
/// (for a gemm with t dividing m and n this is the blocked algorithm's exact count
/// mk⌈n/t⌉ + kn⌈m/t⌉ = 2mnk/t; Hong and Kung, STOC 1981, bound any schedule's traffic below
/// by Ω(W / √M), so this is within a constant of optimal). Not calibrated.
struct SpillTraffic {
  std::int64_t read_bytes = 0, write_bytes = 0;
  std::int64_t bytes() const { return read_bytes + write_bytes; }
};
SpillTraffic op_spill_traffic(const trace::OpRecord& op, const BackendConfig& config);

/// The ops an accelerable kernel runs: its recorded ops, or, when the trace recorded none, the
/// ops its descriptor derives from its sizes (arch/kernels: AccelerableKernel::derive_ops).
/// Throws std::runtime_error for a kernel without ops that has no descriptor.
std::vector<trace::OpRecord> kernel_ops(const trace::KernelRecord& kernel,
                                        const BackendConfig& config);

/// Σ op_cycles over kernel_ops(kernel): the kernel's cycles on an idle accelerator (its ops run
/// one after another: each needs the previous one's result).
std::int64_t kernel_cycles(const trace::KernelRecord& kernel, const BackendConfig& config);
/// kernel_cycles / clock.
double kernel_seconds(const trace::KernelRecord& kernel, const BackendConfig& config);
/// What a scheduler that knows only a kernel's sizes calls (Sec. VI-B: accelerator time from the
/// latency profiles of the five building blocks): kernel_seconds of the ops kernel_ops() derives
/// for `kernel` (an accelerable kernel, arch/kernels) with sizes m, n (docs/TRACE.md).
double predict_kernel_seconds(const std::string& kernel, std::int64_t m, std::int64_t n,
                              const BackendConfig& config);

}  // namespace edx::arch
