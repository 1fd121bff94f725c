#pragma once
// The configured datapath of the backend accelerator (paper Sec. VI-A, Fig. 14): one clock, the
// five building blocks of Table II (matrix multiplication, decomposition, inverse, transpose,
// forward/back substitution) with their sizes, the scratchpad holding the operands, and the two
// structure optimizations (symmetric S; diagonal + 6x6 inverse). Parsed from the `backend:`
// section of a platform YAML; every field has a default, unknown keys are errors. The unit sizes
// are public so that the cost model (arch/cost) can read them.
//
// Defaults are Edx-Car's sizes (configs/edx_car.yaml repeats them). The paper gives no unit
// sizes; docs/MODEL.md ("Backend unit sizes") derives them from Table III: the DSP the frontend
// leaves (1284 x (1 - 80.2 %) = 254) holds about 18 double-precision MACs (14 DSP each, PG060),
// i.e. a 4x4 array and one MAC lane for each of decomposition, inverse and substitution. The
// same numbers size the timing (op_timing) and the resources (arch/cost). Edx-Car "uses a larger
// matrix multiplication/decomposition unit" than Edx-Drone (Sec. VII-A), which configs/
// edx_drone.yaml expresses through gemm_block.
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "arch/common/config_fields.hpp"
#include "arch/kernels/kernels.hpp"

namespace YAML {
class Node;
}

namespace edx::arch {

struct BackendConfig {
  double clock_mhz = 150.0;  ///< assumed: the frontend's HLS clock on Virtex-7
  // Matrix multiplication unit: a b x b output-stationary systolic array (b^2 MACs a cycle).
  int gemm_block = 4;  ///< b (assumed; Table III DSP budget, docs/MODEL.md)
  // Decomposition unit (blocked Cholesky / LDL^T): b_d x b_d multiply-accumulate lanes.
  int decomp_block = 1;  ///< b_d (assumed): b_d^2 MAC lanes
  // Inverse unit: reciprocal and multiply-accumulate lanes; specialized for [A B; B^T D] with A
  // diagonal and D 6x6 (structured_inverse), general Gauss-Jordan otherwise.
  int inverse_lanes = 1;  ///< (assumed)
  // Transpose unit: words moved a cycle (one SPM read and write port pair per word).
  int transpose_words_per_cycle = 4;  ///< (assumed)
  // Forward/back substitution unit: multiply-accumulate lanes.
  int trsv_lanes = 1;  ///< (assumed)
  // Latencies of the pipelined double-precision divider and square root (a reciprocal or a root
  // is on the critical path of every pivot / column).
  int divide_latency_cycles = 30;  ///< (assumed; order of a pipelined double divider)
  int sqrt_latency_cycles = 30;    ///< (assumed)
  /// Bytes of one matrix element, in the units, the SPM and on the link: 8 (IEEE 754 double)
  /// or 4 (single). Also selects the units' MACs in the cost model (double or single).
  int scalar_bytes = 8;

  /// MAC lanes of the decomposition unit: b_d^2 (what the timing and the cost model both use).
  int decomp_lanes() const { return decomp_block * decomp_block; }
  /// One scratchpad shared by the units, holding the operands of the running op ("the SPMs need
  /// to accommodate the size of the entire input matrices", Sec. VI-A). Assumed 1.25 MiB: within
  /// the BRAM Edx-Car leaves to the backend (26.5 % of 5.0 MB, Sec. VII-B).
  std::int64_t spm_bytes = 1310720;
  /// S = H P H^T is symmetric: compute only the blocks on and above the diagonal of symmetric
  /// results, store symmetric matrices as triangles (Sec. VI-A, "Optimization").
  bool symmetric_optimization = true;
  /// A_mm = [A B; B^T D], A diagonal, D 6x6: reciprocals + a 6x6 inverse (Sec. VI-A).
  bool structured_inverse = true;
  /// Output-stationary array with double-buffered accumulators: the next tile's operands stream
  /// in while the previous tile's results shift out, so back-to-back tiles cost max(k, b) cycles
  /// each and the 2b fill/drain is paid once per op (else once per tile). Assumed.
  bool gemm_overlap_tiles = false;
  /// Blocked factorizations and substitutions ("the inherent blocking nature of matrix
  /// operations", Sec. VI-A): in b x b blocks (b = gemm_block), the decomposition and
  /// substitution units handle the diagonal blocks and the O(n^3) trailing updates run as gemm /
  /// syrk on the multiplication array (else the whole op runs on its own unit). Assumed.
  bool blocked_solvers = false;
  // The marginalization problem's shape where the trace does not record it (an ops-less
  // kernel: kernel_ops(); its link transfers: kernel_transfer()): A_mm is (m l + p) square.
  int pose_dim = 6;      ///< p: pose degrees of freedom of the marginalized keyframe
  int landmark_dim = 1;  ///< l: parameters per landmark (inverse depth in the SLAM backend)

  /// What the link model needs of the kernels' matrices (one home: these `backend:` keys).
  KernelMatrixFormat matrix_format() const { return {scalar_bytes, pose_dim, landmark_dim}; }
  /// Every key of `backend:` (docs/CONFIG.md).
  static const FieldList<BackendConfig>& fields();
  /// Throws std::runtime_error naming the field and the accepted range ("backend.gemm_block: ...").
  void validate() const;
  nlohmann::json to_json() const;
  /// Reads the fields present in `node` (a map) over the defaults; errors name file, line and
  /// key: "car.yaml:12: backend.gemm_block: expected an integer >= 1, got 0".
  static BackendConfig from_yaml(const YAML::Node& node, const std::string& where,
                                 const std::string& prefix = "backend");
};

}  // namespace edx::arch
