#pragma once
// The backend accelerator as configured (paper Sec. VI-A, Fig. 14): its matrix units, as
// instances of registered unit kinds (matrix_unit.hpp, arch/backend/units/), and what they share:
// the clock, the scratchpad holding the running op's operands, the scalar format in the SPM and on
// the link, and the symmetric-S optimization. Parsed from the `backend:` section of a platform
// YAML; every field has a default, unknown keys are errors.
//
// The defaults are Edx-Car's design (configs/edx_car.yaml repeats them): the five building blocks
// of Table II, one instance each, sized from Table III's DSP budget (docs/MODEL.md, "Backend unit
// sizes": the 254 DSP the frontend leaves hold about 18 double MACs, a 4x4 array and one lane each
// for decomposition, inverse and substitution). The same instances size the timing (op_timing)
// and the resources (arch/cost).
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "arch/backend/matrix_unit.hpp"
#include "arch/kernels/kernels.hpp"
#include "common/config_fields.hpp"

namespace YAML {
class Node;
}

namespace edx::arch {

struct BackendConfig {
  double clock_mhz = 150.0;  ///< the units' clock unless an instance says (assumed: HLS clock)
  /// The backend's arithmetic, IEEE 754 double or single: every unit's MACs, dividers and roots
  /// (cost, energy), and the bytes of one matrix element in the SPM and on the link. It must be
  /// the trace's (meta precision: what the offloadable kernels were computed in).
  trace::Precision precision = trace::Precision::kFp64;
  /// One scratchpad shared by the units, holding the operands of the running op ("the SPMs need
  /// to accommodate the size of the entire input matrices", Sec. VI-A). Assumed 1.25 MiB: within
  /// the BRAM Edx-Car leaves to the backend (26.5 % of 5.0 MB, Sec. VII-B).
  std::int64_t spm_bytes = 1310720;
  /// S = H P H^T is symmetric: compute only the blocks on and above the diagonal of symmetric
  /// results, store symmetric matrices as triangles (Sec. VI-A, "Optimization").
  bool symmetric_optimization = true;
  // The marginalization problem's shape where the trace does not record it (an ops-less
  // kernel: kernel_ops(); its link transfers: kernel_transfer()): A_mm is (m l + p) square.
  int pose_dim = 6;      ///< p: pose degrees of freedom of the marginalized keyframe
  int landmark_dim = 1;  ///< l: parameters per landmark (inverse depth in the SLAM backend)
  /// The matrix units: paper_backend_units(), then what `backend.units` lists over them by name
  /// (a default unit's keys overridden, its kind kept unless given; a new name added, its kind
  /// required; count: 0 leaves a unit out).
  std::vector<MatrixUnitInstance> units = paper_backend_units();

  /// The instance serving `op` (count > 0), nullptr when none does.
  const MatrixUnitInstance* unit_for(trace::Op op) const;
  /// An instance's clock: its own, else clock_mhz.
  double clock_of(const MatrixUnitInstance& unit) const;
  /// What the link model needs of the kernels' matrices (one home: these `backend:` keys).
  KernelMatrixFormat matrix_format() const { return {scalar_bytes(), pose_dim, landmark_dim}; }
  /// Bytes of one matrix element at `precision`: 8 (fp64) or 4 (fp32).
  int scalar_bytes() const { return trace::scalar_bytes(precision); }
  /// The keys of `backend:` besides `units` (docs/CONFIG.md).
  static const FieldList<BackendConfig>& fields();
  /// Throws std::runtime_error naming the field ("backend.units.gemm: ...", "backend.spm_bytes:
  /// ..."): field ranges, and every trace op served by at most one instance.
  void validate() const;
  nlohmann::json to_json() const;
  /// Reads the keys of a `backend:` map over the defaults (the registry's hook for kind
  /// fpga_matrix_units, which then refuses unread keys and validates); errors name file, line
  /// and key: "car.yaml:12: backend.units.gemm.block: expected an integer in [1, 256], got 0".
  static BackendConfig parse(YamlFields& fields);
  /// Every key of the kind: its fields, `units`, `units.<name>` and each registered unit kind;
  /// its own table headed `heading`.
  static std::vector<ReferenceRow> reference(const std::string& section,
                                             const std::string& heading);

  /// The five building blocks of Table II, one instance each, each kind at its defaults (Edx-Car's
  /// sizes, docs/MODEL.md "Backend unit sizes"): gemm (systolic_array 4x4), decomposition (one
  /// lane), inverse (one lane, structured), transpose (4 words a cycle), substitution (one lane).
  static std::vector<MatrixUnitInstance> paper_backend_units();
};

}  // namespace edx::arch
