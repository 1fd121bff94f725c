#pragma once
// The three host <-> FPGA transfers of every frame (paper Sec. VII-A: "the first time from the
// FPGA, which transfers the frontend results and the IMU/GPS samples to the host; the second
// time from the host, which passes the inputs of a backend kernel (e.g. the H, P and R matrices
// to calculate Kalman gains) to the FPGA, and the last time transferring the backend results
// back to the host"), sized from one trace frame (docs/TRACE.md). docs/MODEL.md, "Links".
//
// (1) FPGA -> host: F left features x feature record + IMU samples x bytes + GPS samples x bytes
//     F = the left FC task's keypoints (tracked + new features; MO's keypoints if no FC row).
//     Feature record (default 14 B, the paper's "2 -- 3 KB on average" (Sec. V-A) at about 140 --
//     220 features):
//       track id u32 (4) + left x, y and right x, y in Q12.4 fixed point (4 x 2) + disparity
//       Q8.8 (2) [+ descriptor, 32 B for 256-bit rBRIEF, off by default].
//     GPS samples only on frames with gps_available.
// (2) host -> FPGA and (3) FPGA -> host, per accelerable kernel, s bytes per scalar (8: double;
//     s, p and l are `backend:` keys, KernelMatrixFormat),
//     sym(n) = n(n+1)/2 when symmetric matrices are packed, else n^2:
//   projection       (m = M map points):  in  C 3x4 + X 4xM      = (12 + 4M) s
//                                          out 2xM image points   = 2M s
//   kalman_gain      (m = rows of H, n = state): in H mxn + P nxn (sym) + R diagonal m
//                                          = (mn + sym(n) + m) s;  out K nxm = nm s
//   marginalization  (m = landmarks, n = kept state; d_l = m * l, l parameters per landmark,
//                     p = 6 pose parameters, d_m = d_l + p):
//                    in  A_mm as its blocks [A B; B^T D] (paper Sec. VI-A): A block-diagonal
//                        m l^2, B d_l x p, D p x p (sym) ; A_mr d_m x n ; A_rr n x n (sym) ;
//                        b_m d_m ; b_r n
//                    out prior A_rr - A_rm A_mm^-1 A_mr n x n (sym) + prior b n
//     l: the kernel's detail "landmark_dim" if given, else (inverse op size - p) / m when the
//     kernel records the A_mm inverse, else the configured backend.landmark_dim.
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "arch/kernels/kernels.hpp"
#include "arch/link/link.hpp"
#include "common/config_fields.hpp"
#include "workloads/trace/records.hpp"

namespace YAML {
class Node;
}

namespace edx::arch {

/// Sizes of the per-frame records; every field is a parameter (docs/MODEL.md).
struct FrameTransferConfig {
  int feature_id_bytes = 4;        ///< u32 track id
  int coordinate_bytes = 2;        ///< per coordinate, Q12.4 (4 fraction bits; 4096 px range)
  int disparity_bytes = 2;         ///< Q8.8
  int descriptor_bytes = 0;        ///< 32 to ship 256-bit rBRIEF descriptors (off: the backend
                                   ///< uses positions only)
  int imu_samples_per_frame = 10;  ///< EuRoC: 200 Hz IMU / 20 Hz camera (Burri et al. 2016)
  int imu_sample_bytes = 56;       ///< i64 time stamp + 3 gyro + 3 accel doubles
  int gps_samples_per_frame = 1;   ///< on frames with GPS (ASSUMPTION: one fix per frame)
  int gps_sample_bytes = 32;       ///< i64 time stamp + 3 position doubles
  bool pack_symmetric = false;     ///< ship symmetric matrices as upper triangles

  /// Bytes of one feature record: id + 4 coordinates + disparity + descriptor.
  std::int64_t feature_record_bytes() const;
  /// Every key of `transfers:` (docs/CONFIG.md).
  static const FieldList<FrameTransferConfig>& fields();
  /// Throws std::runtime_error naming the bad field: "transfers.imu_sample_bytes: expected ...".
  void validate() const;
  nlohmann::json to_json() const;
  /// Reads a `transfers:` map over the defaults; errors name file, line and key.
  static FrameTransferConfig from_yaml(const YAML::Node& node, const std::string& where,
                                       const std::string& prefix = "transfers");
};

/// Inputs and results of one accelerable kernel invocation.
struct KernelTransfer {
  std::string kernel;
  std::int64_t input_bytes = 0;   ///< host -> FPGA
  std::int64_t output_bytes = 0;  ///< FPGA -> host
};

/// Transfer (1) of one frame: its frontend results and sensor samples, FPGA -> host.
struct FrameTransfers {
  std::int64_t frame_id = 0;
  std::int64_t features = 0;        ///< F
  std::int64_t frontend_bytes = 0;  ///< F x feature record
  std::int64_t imu_bytes = 0;
  std::int64_t gps_bytes = 0;

  /// (1) FPGA -> host: frontend results + IMU + GPS.
  std::int64_t frontend_to_host() const { return frontend_bytes + imu_bytes + gps_bytes; }
  nlohmann::json to_json() const;
};

/// Inputs and results of one accelerable kernel (from its name, sizes, detail and ops' sizes, never
/// a host time); throws std::runtime_error for an unknown accelerable kernel or negative sizes.
KernelTransfer kernel_transfer(const trace::KernelRecord& kernel, const FrameTransferConfig& config,
                               const KernelMatrixFormat& format);

/// Transfer (1) of `frame`; (2) and (3) are each offloaded kernel's (kernel_transfer).
FrameTransfers frontend_transfer(const trace::FrameTrace& frame, const FrameTransferConfig& config);

/// Inputs + results of one kernel on an idle link: transfer_time(in) + transfer_time(out)
/// (what offloading that kernel adds to its compute time).
sim::Time kernel_transfer_time(const Link& link, const KernelTransfer& kernel);

}  // namespace edx::arch
