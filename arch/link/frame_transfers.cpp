#include "arch/link/frame_transfers.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <stdexcept>

#include "arch/common/yaml_fields.hpp"

namespace edx::arch {
namespace {

/// Scalars of an n x n symmetric matrix: n(n+1)/2 packed, n^2 full.
std::int64_t symmetric(std::int64_t n, bool packed) { return packed ? n * (n + 1) / 2 : n * n; }

/// The left image's feature count: FC L keypoints, else MO keypoints, else 0.
std::int64_t left_features(const trace::FrameTrace& frame) {
  for (const trace::TaskRecord& t : frame.tasks) {
    if (t.task == trace::Task::FC && t.image == trace::Image::Left) return t.keypoints;
  }
  for (const trace::TaskRecord& t : frame.tasks) {
    if (t.task == trace::Task::MO) return t.keypoints;
  }
  return 0;
}

/// Parameters per landmark of a marginalization record (see frame_transfers.hpp).
std::int64_t landmark_dim(const trace::KernelRecord& k, const KernelMatrixFormat& c) {
  if (!k.detail_json.empty()) {
    nlohmann::json detail;
    try {
      detail = nlohmann::json::parse(k.detail_json);
    } catch (const nlohmann::json::exception&) {
      throw std::runtime_error(fmt::format("kernel '{}': detail: expected a JSON object, got '{}'",
                                           k.kernel, k.detail_json));
    }
    if (detail.is_object() && detail.contains("landmark_dim")) {
      const nlohmann::json& v = detail["landmark_dim"];
      if (!v.is_number_integer() || v.get<std::int64_t>() < 1) {
        throw std::runtime_error(
            fmt::format("kernel '{}': detail.landmark_dim: expected an integer >= 1, got {}",
                        k.kernel, v.dump()));
      }
      return v.get<std::int64_t>();
    }
  }
  if (k.m > 0) {
    for (const trace::OpRecord& op : k.ops) {
      const std::int64_t landmark_part = op.m - c.pose_dim;
      if (op.op == trace::Op::Inverse && landmark_part > 0 && landmark_part % k.m == 0) {
        return landmark_part / k.m;  // A_mm inverse: d_m = m l + p
      }
    }
  }
  return c.landmark_dim;
}

}  // namespace

std::int64_t FrameTransferConfig::feature_record_bytes() const {
  return feature_id_bytes + 4 * std::int64_t{coordinate_bytes} + disparity_bytes + descriptor_bytes;
}

const FieldList<FrameTransferConfig>& FrameTransferConfig::fields() {
  using C = FrameTransferConfig;
  static const FieldList<C> list = {
      field("feature_id_bytes", &C::feature_id_bytes, "bytes", "track id of a feature record",
            Bounds::at_least(0)),
      field("coordinate_bytes", &C::coordinate_bytes, "bytes",
            "one image coordinate (Q12.4); a record has four", Bounds::at_least(1)),
      field("disparity_bytes", &C::disparity_bytes, "bytes", "stereo disparity (Q8.8)",
            Bounds::at_least(0)),
      field("descriptor_bytes", &C::descriptor_bytes, "bytes",
            "descriptor shipped with a feature (32: 256-bit rBRIEF; 0: positions only)",
            Bounds::at_least(0)),
      field("imu_samples_per_frame", &C::imu_samples_per_frame, "",
            "IMU samples per camera frame (EuRoC: 200 Hz / 20 Hz)", Bounds::at_least(0)),
      field("imu_sample_bytes", &C::imu_sample_bytes, "bytes",
            "one IMU sample: time stamp + 3 gyro + 3 accel doubles", Bounds::at_least(0)),
      field("gps_samples_per_frame", &C::gps_samples_per_frame, "",
            "GPS fixes per frame that has GPS (assumed 1)", Bounds::at_least(0)),
      field("gps_sample_bytes", &C::gps_sample_bytes, "bytes",
            "one GPS fix: time stamp + 3 position doubles", Bounds::at_least(0)),
      field("pack_symmetric", &C::pack_symmetric, "",
            "ship symmetric matrices as upper triangles n(n+1)/2"),
  };
  return list;
}

void FrameTransferConfig::validate() const { check_fields(*this, "transfers", fields()); }

nlohmann::json FrameTransferConfig::to_json() const {
  nlohmann::json j = fields_to_json(*this, fields());
  j["feature_record_bytes"] = feature_record_bytes();
  return j;
}

FrameTransferConfig FrameTransferConfig::from_yaml(const YAML::Node& node, const std::string& where,
                                                   const std::string& prefix) {
  return parse_section<FrameTransferConfig>(node, where, prefix);
}

std::int64_t FrameTransfers::kernel_inputs_to_fpga() const {
  std::int64_t sum = 0;
  for (const KernelTransfer& k : kernels) sum += k.input_bytes;
  return sum;
}

std::int64_t FrameTransfers::kernel_results_to_host() const {
  std::int64_t sum = 0;
  for (const KernelTransfer& k : kernels) sum += k.output_bytes;
  return sum;
}

std::int64_t FrameTransfers::total() const {
  return frontend_to_host() + kernel_inputs_to_fpga() + kernel_results_to_host();
}

nlohmann::json FrameTransfers::to_json() const {
  nlohmann::json list = nlohmann::json::array();
  for (const KernelTransfer& k : kernels) {
    list.push_back({{"kernel", k.kernel},
                    {"input_bytes", k.input_bytes},
                    {"output_bytes", k.output_bytes},
                    {"parts", k.parts}});
  }
  return {{"frame_id", frame_id},
          {"features", features},
          {"frontend_bytes", frontend_bytes},
          {"imu_bytes", imu_bytes},
          {"gps_bytes", gps_bytes},
          {"frontend_to_host", frontend_to_host()},
          {"kernel_inputs_to_fpga", kernel_inputs_to_fpga()},
          {"kernel_results_to_host", kernel_results_to_host()},
          {"total", total()},
          {"kernels", list}};
}

KernelTransfer kernel_transfer(const trace::KernelRecord& k, const FrameTransferConfig& c,
                               const KernelMatrixFormat& format) {
  if (k.m < 0 || k.n < 0 || k.k < 0) {
    throw std::runtime_error(fmt::format("kernel '{}': expected sizes m, n, k >= 0, got {}, {}, {}",
                                         k.kernel, k.m, k.n, k.k));
  }
  KernelTransfer t;
  t.kernel = k.kernel;
  nlohmann::json in = nlohmann::json::object();
  nlohmann::json out = nlohmann::json::object();
  const std::int64_t s = format.scalar_bytes;
  if (k.kernel == "projection") {
    const std::int64_t points = k.m;       // M
    in["camera_matrix"] = 12 * s;          // C 3x4
    in["points"] = 4 * points * s;         // X 4xM homogeneous
    out["image_points"] = 2 * points * s;  // 2xM
  } else if (k.kernel == "kalman_gain") {
    const std::int64_t rows = k.m, state = k.n;
    in["H"] = rows * state * s;                        // m x n
    in["P"] = symmetric(state, c.pack_symmetric) * s;  // n x n covariance
    in["R"] = rows * s;                                // diagonal m x m
    out["K"] = state * rows * s;                       // n x m
  } else if (k.kernel == "marginalization") {
    const std::int64_t landmarks = k.m, kept = k.n;
    const std::int64_t l = landmark_dim(k, format);
    const std::int64_t p = format.pose_dim;
    const std::int64_t dl = landmarks * l;               // d_l
    const std::int64_t dm = dl + p;                      // d_m
    in["A_mm.A"] = landmarks * l * l * s;                // block-diagonal, m blocks l x l
    in["A_mm.B"] = dl * p * s;                           // d_l x p
    in["A_mm.D"] = symmetric(p, c.pack_symmetric) * s;   // p x p
    in["A_mr"] = dm * kept * s;                          // d_m x n
    in["A_rr"] = symmetric(kept, c.pack_symmetric) * s;  // n x n
    in["b_m"] = dm * s;
    in["b_r"] = kept * s;
    out["prior_H"] = symmetric(kept, c.pack_symmetric) * s;  // Schur complement n x n
    out["prior_b"] = kept * s;
  } else {
    throw std::runtime_error(fmt::format(
        "kernel '{}': expected an accelerable kernel projection, kalman_gain or marginalization",
        k.kernel));
  }
  for (const auto& [name, bytes] : in.items()) t.input_bytes += bytes.get<std::int64_t>();
  for (const auto& [name, bytes] : out.items()) t.output_bytes += bytes.get<std::int64_t>();
  t.parts = {{"inputs", in}, {"outputs", out}};
  return t;
}

FrameTransfers frontend_transfer(const trace::FrameTrace& frame, const FrameTransferConfig& c) {
  FrameTransfers t;
  t.frame_id = frame.frame.frame_id;
  t.features = left_features(frame);
  t.frontend_bytes = t.features * c.feature_record_bytes();
  t.imu_bytes = std::int64_t{c.imu_samples_per_frame} * c.imu_sample_bytes;
  t.gps_bytes =
      frame.frame.gps_available ? std::int64_t{c.gps_samples_per_frame} * c.gps_sample_bytes : 0;
  return t;
}

FrameTransfers frame_transfers(const trace::FrameTrace& frame, const FrameTransferConfig& c,
                               const KernelMatrixFormat& format) {
  FrameTransfers t = frontend_transfer(frame, c);
  for (const trace::KernelRecord& k : frame.kernels) {
    if (!k.accelerable) continue;
    try {
      t.kernels.push_back(kernel_transfer(k, c, format));
    } catch (const std::runtime_error& e) {
      throw std::runtime_error(fmt::format("frame {}: {}", frame.frame.frame_id, e.what()));
    }
  }
  return t;
}

nlohmann::json FrameTransferTimes::to_json() const {
  return {{"frontend_to_host_us", sim::to_us(frontend_to_host)},
          {"kernel_inputs_to_fpga_us", sim::to_us(kernel_inputs_to_fpga)},
          {"kernel_results_to_host_us", sim::to_us(kernel_results_to_host)},
          {"total_us", sim::to_us(total())}};
}

sim::Time kernel_transfer_time(const LinkSpec& link, const KernelTransfer& kernel) {
  return transfer_time(link, kernel.input_bytes) + transfer_time(link, kernel.output_bytes);
}

FrameTransferTimes frame_transfer_times(const LinkSpec& link, const FrameTransfers& transfers) {
  FrameTransferTimes t;
  t.frontend_to_host = transfer_time(link, transfers.frontend_to_host());
  for (const KernelTransfer& k : transfers.kernels) {
    t.kernel_inputs_to_fpga += transfer_time(link, k.input_bytes);
    t.kernel_results_to_host += transfer_time(link, k.output_bytes);
  }
  return t;
}

}  // namespace edx::arch
