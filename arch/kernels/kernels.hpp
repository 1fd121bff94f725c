#pragma once
// The backend kernels the accelerator can run (the paper's three of Sec. VI-A, Table II, and others
// whose matrix ops the trace records), one descriptor each: the one place that knows a kernel by
// its trace name. Which of them a platform offloads is its scheduler.offload. What the models need
// of a kernel is here:
//   - the ops it runs when the trace recorded none, derived from its sizes (op_timing's
//     kernel_ops, the scheduler's prediction from the latency profiles, Sec. VI-B);
//   - its operands (transfer 2, host -> FPGA) and results (transfer 3) in bytes, by matrix
//     (frame_transfers);
//   - the degree of the scheduler's host-time polynomial in its size (scheduler).
// A new kernel is one file beside projection.cpp, kalman_gain.cpp and marginalization.cpp and
// one line of the registry in kernels.cpp (docs/MODEL.md, "Accelerable kernels").
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "workloads/trace/records.hpp"

namespace edx::arch {

/// The pose block of the structured inverse (Sec. VI-A: "6 represents the number of degrees of
/// freedom in a pose").
inline constexpr std::int64_t kPoseBlock = 6;

/// What a kernel's matrices look like; its one home is the `backend:` section
/// (BackendConfig::matrix_format()).
struct KernelMatrixFormat {
  std::int64_t scalar_bytes;  ///< s: bytes of one element
  std::int64_t pose_dim;      ///< p, where the trace does not say
  std::int64_t landmark_dim;  ///< l, where the trace does not say
};

/// sym(n) = n(n+1)/2 elements of a symmetric n x n matrix stored as a triangle, else n².
std::int64_t symmetric_elements(std::int64_t n, bool packed);

/// Operand (transfer 2) and result (transfer 3) bytes of one invocation, by matrix name.
struct KernelOperands {
  nlohmann::json inputs = nlohmann::json::object();
  nlohmann::json outputs = nlohmann::json::object();
};

struct AccelerableKernel {
  std::string_view name;   ///< the trace's kernel name
  std::string_view mode;   ///< the backend mode that runs it
  std::string_view what;   ///< what it computes, and where the paper says so
  std::string_view sizes;  ///< what the trace's m and n are
  /// Degree of the scheduler's host-time polynomial in the kernel's size (Sec. VI-B).
  int host_model_degree = 1;
  /// Its result is combined with an operand by an addition on the "Misc." block of Fig. 14
  /// (S = H P Hᵀ + R; P - K P Hᵀ ...): what the non-shared design replicates that adder for.
  bool misc_add = true;
  /// Its ops from sizes m, n, mirroring what the backend records (for traces without ops);
  /// nullptr for a kernel whose ops only the trace knows (an invocation without recorded ops
  /// then did no matrix work and stays on the host).
  std::vector<trace::OpRecord> (*derive_ops)(std::int64_t m, std::int64_t n,
                                             const KernelMatrixFormat& format) = nullptr;
  /// Its operands and results in bytes (s bytes a scalar; symmetric matrices packed as
  /// triangles when `pack_symmetric`). Sizes are checked by the caller (>= 0).
  KernelOperands (*operands)(const trace::KernelRecord& kernel, const KernelMatrixFormat& format,
                             bool pack_symmetric) = nullptr;
  /// The op kinds it runs, for a kernel without derive_ops (Table II's column of it).
  std::vector<trace::Op> op_kinds = {};
};

/// The integer `key` of a kernel's detail JSON, std::nullopt when absent. Throws
/// std::runtime_error naming the kernel when the detail is not a JSON object or the value not an
/// integer >= `min`.
std::optional<std::int64_t> detail_integer(const trace::KernelRecord& kernel, std::string_view key,
                                           std::int64_t min = 0);

/// Every accelerable kernel, in registry order.
const std::vector<const AccelerableKernel*>& accelerable_kernels();
/// The kernel called `name`, nullptr when there is none.
const AccelerableKernel* find_accelerable_kernel(std::string_view name);
/// The kernel called `name`; throws std::runtime_error "kernel 'x': expected an accelerable
/// kernel (projection, kalman_gain or marginalization)" otherwise.
const AccelerableKernel& accelerable_kernel(std::string_view name);
/// "projection, kalman_gain or marginalization".
std::string accelerable_kernel_names();

// The descriptors (one file each): the paper's three, then kernels beyond the paper that a
// platform may offload (scheduler.offload).
const AccelerableKernel& projection_kernel();
const AccelerableKernel& kalman_gain_kernel();
const AccelerableKernel& marginalization_kernel();
const AccelerableKernel& schur_complement_kernel();
const AccelerableKernel& covariance_update_kernel();
const AccelerableKernel& gps_fusion_kernel();
const AccelerableKernel& nullspace_projection_kernel();
const AccelerableKernel& normal_equations_kernel();
const AccelerableKernel& solve_kernel();
const AccelerableKernel& compression_kernel();
const AccelerableKernel& covariance_propagation_kernel();

/// The paper's accelerated kernels (Sec. VI-A, Table II), the default of scheduler.offload.
std::vector<std::string> paper_offload_set();

}  // namespace edx::arch
