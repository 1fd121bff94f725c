#pragma once
// The matrix ops of the trace (docs/TRACE.md, ops table) on the backend accelerator's units (paper
// Sec. VI-A, Table II): which instance serves an op, its cycles there (the unit kind's own
// formula, arch/backend/units/), and the scratchpad bytes its operands take. These are the
// "latency profiles of the five building blocks" the runtime scheduler estimates accelerator time
// from (Sec. VI-B): a scheduler calls op_cycles() per op, or kernel_cycles() per kernel. Every
// formula is listed in docs/MODEL.md ("Backend accelerator"); ceil(x / y) is written ⌈x/y⌉.
//
// Symmetric matrices (op flag kSymmetric, "result or operand is symmetric"): a syrk's result is
// symmetric; for a gemm the flag is read as: the result when it is square (m == n: S = H P H^T,
// the SLAM prior H* = A_rr - A_rm A_mm^-1 A_mr), else the square operand (A when m == k: P in
// P H^T; B when k == n: A_mm^-1 in A_rm A_mm^-1). With symmetric_optimization a symmetric result
// is computed as its blocks on and above the diagonal, and any symmetric matrix is stored as a
// triangle, sym(n) = n(n+1)/2 scalars (else n^2).
#include <cstdint>
#include <string>
#include <vector>

#include "arch/backend/backend_config.hpp"
#include "arch/backend/matrix_unit.hpp"
#include "arch/backend/offload_accelerator.hpp"
#include "arch/kernels/kernels.hpp"
#include "workloads/trace/records.hpp"

namespace edx::arch {

/// ⌈a / b⌉ for a >= 0, b >= 1.
inline std::int64_t ceil_div(std::int64_t a, std::int64_t b) { return (a + b - 1) / b; }
/// Scalars of an n x n symmetric matrix as stored: n(n+1)/2 with the optimization, else n^2.
std::int64_t symmetric_scalars(std::int64_t n, const BackendConfig& config);
/// True when a gemm's (square) result is symmetric (see above).
bool symmetric_gemm_result(const trace::OpRecord& op);
/// Throws std::runtime_error for negative dimensions.
void check_dimensions(const trace::OpRecord& op);

/// Multiply-adds of an unblocked n x n Cholesky or LDL^T (right-looking): the trailing updates
/// Σ_{j<n} (n-j-1)(n-j)/2 = (n^3 - n)/6 plus the column scalings by the pivot's reciprocal
/// Σ_{j<n} (n-j-1) = n(n-1)/2. (LDL^T updates a_ik -= l_ij a_kj with the unscaled a_kj, so it
/// needs no more products than Cholesky.)
std::int64_t factorization_macs(std::int64_t n);

/// Multiply-adds of a Householder QR of an m x n matrix: per reflector j < min(m, n) the column's
/// norm (r_j = m - j) and its application to the n - j - 1 columns right of it (2 r_j each):
/// Σ_j r_j (1 + 2(n - j - 1)) ≈ mn² - n³/3 (LAPACK Working Note 41: 2mn² - 2n³/3 flops).
std::int64_t householder_macs(std::int64_t m, std::int64_t n);

/// The instance serving `op`; throws std::runtime_error "no backend unit serves <op>" when none
/// does (offloadable() says beforehand).
const MatrixUnitInstance& serving_unit(trace::Op op, const BackendConfig& config);

/// Cycles of one op on its instance, all its copies sharing the work (the kind's formula,
/// arch/backend/units/; docs/MODEL.md lists each); a batch of independent instances by the kind's
/// MatrixUnit::batch_cycles. Throws std::runtime_error for negative dimensions, a batch below 1
/// or an op no instance serves.
std::int64_t op_cycles(const trace::OpRecord& op, const BackendConfig& config);
/// The same on `copies` copies of its instance (the DES when some copies are busy).
std::int64_t op_cycles(const trace::OpRecord& op, int copies, const BackendConfig& config);

/// Scalars an op reads (its operands) and writes (its result) at least once, stored as
/// op_spm_bytes stores them (sym(n) for a symmetric matrix with the optimization), unless its
/// unit stores them its own way (MatrixUnit::own_operands: the structured inverse):
///   gemm  in mk + kn, out mn          syrk  in mk, out sym(m)
///   potrf, ldlt  in sym(m), out sym(m)       trsm, trsv  in sym(m) + m·rhs, out m·rhs
///   transpose  in mn, out mn          inverse  in m^2, out m^2 (sym(m) each when kSymmetric;
///                                              m each when kDiagonal)
///   qr  in mn, out mn (R and the reflectors in place)
/// of one instance of a batch (the scratchpad holds the running instance's operands).
OperandScalars op_operand_scalars(const trace::OpRecord& op, const BackendConfig& config);

/// Scratchpad bytes of one op's operands and result (Sec. VI-A: "the input matrices must be
/// ready before an operation starts"), s bytes a scalar: in + out scalars, or in only for the
/// in-place ops (potrf, ldlt, qr overwrite their matrix; trsm, trsv their right-hand side); of
/// one instance of a batch.
std::int64_t op_spm_bytes(const trace::OpRecord& op, const BackendConfig& config);

/// Multiply-adds W of one op, the work a tiled out-of-core algorithm re-reads operands for,
/// unless its unit computes it its own way (MatrixUnit::own_macs: the structured inverse):
///   gemm mnk (k sym(m) for a symmetric result with the optimization)   syrk k sym(m)
///   potrf, ldlt factorization_macs(m)     trsm, trsv rhs m(m+1)/2      transpose 0
///   inverse m^3 (0 when kDiagonal: reciprocals)   qr householder_macs(m, n)
/// times the batch.
std::int64_t op_macs(const trace::OpRecord& op, const BackendConfig& config);

/// SPM tile side of an op that spills: t = max(1, ⌊√(M / 3)⌋), M = spm_bytes / s the SPM's
/// capacity in scalars: three t x t tiles (two operand tiles and the resident accumulator) fill
/// it (the tiled matrix multiply; Lam, Rothberg and Wolf, ASPLOS 1991).
std::int64_t spill_tile(const BackendConfig& config);

/// DRAM traffic of one op run out of core (docs/MODEL.md, "SPM spills"); zero when the op fits
/// the SPM (op_spm_bytes <= spm_bytes). Tiled at t = spill_tile(): each t x t x t block of its W
/// multiply-adds reads two t x t operand tiles while the accumulator tile stays in the SPM, so
/// the op reads 2W / t scalars (every operand at least once) and writes its result once:
///   read  = s · max(in, ⌈2W / t⌉),   write = s · out   (W, in, out of one instance; each
///                                                         instance of a batch streams its own)
/// (for a gemm with t dividing m and n this is the blocked algorithm's exact count
/// mk⌈n/t⌉ + kn⌈m/t⌉ = 2mnk/t; Hong and Kung, STOC 1981, bound any schedule's traffic below
/// by Ω(W / √M), so this is within a constant of optimal). Not calibrated.
SpillTraffic op_spill_traffic(const trace::OpRecord& op, const BackendConfig& config);

/// The ops an accelerable kernel runs: its recorded ops, or, when the trace recorded none, the
/// ops its descriptor derives from its sizes (arch/kernels: AccelerableKernel::derive_ops).
/// Throws std::runtime_error for a kernel without ops that has no descriptor.
std::vector<trace::OpRecord> kernel_ops(const trace::KernelRecord& kernel,
                                        const BackendConfig& config);

/// True when `kernel` has ops: recorded, or derivable from its sizes (a kernel without is no
/// matrix work: it stays on the host).
bool has_ops(const trace::KernelRecord& kernel);

/// True when an instance serves every op of `kernel` (else it cannot leave the host).
bool offloadable(const trace::KernelRecord& kernel, const BackendConfig& config);

/// The kernels of `offload` (scheduler.offload) whose ops use instance `unit` of `config` (Table
/// II's columns for the paper's three), from their derived ops: what the non-shared design
/// replicates the unit for.
std::vector<std::string> kernels_using(std::size_t unit, const BackendConfig& config,
                                       const std::vector<std::string>& offload);

/// Σ op_cycles over kernel_ops(kernel): the kernel's cycles on an idle accelerator (its ops run
/// one after another: each needs the previous one's result).
std::int64_t kernel_cycles(const trace::KernelRecord& kernel, const BackendConfig& config);

}  // namespace edx::arch
