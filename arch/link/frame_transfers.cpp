#include "arch/link/frame_transfers.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <stdexcept>

#include "common/yaml_fields.hpp"

namespace edx::arch {
namespace {

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

}  // namespace

std::int64_t FrameTransferConfig::feature_record_bytes() const {
  return feature_id_bytes + 4 * std::int64_t{coordinate_bytes} + disparity_bytes + descriptor_bytes;
}

const FieldList<FrameTransferConfig>& FrameTransferConfig::fields() {
  using C = FrameTransferConfig;
  // A record field or sample of at most 1 KiB (the largest, a descriptor, is 32 B) and at most
  // 10^4 samples a frame (a 10 kHz IMU beside a 1 FPS camera): a frame's transfers then stay
  // within what the DES moves in bounded time (issue 45).
  const Bounds field_bytes = Bounds::at_least(0).at_most(1024);
  const Bounds samples = Bounds::at_least(0).at_most(10000);
  static const FieldList<C> list = {
      field("feature_id_bytes", &C::feature_id_bytes, "bytes", "track id of a feature record",
            field_bytes),
      field("coordinate_bytes", &C::coordinate_bytes, "bytes",
            "one image coordinate (Q12.4); a record has four", Bounds::at_least(1).at_most(1024)),
      field("disparity_bytes", &C::disparity_bytes, "bytes", "stereo disparity (Q8.8)",
            field_bytes),
      field("descriptor_bytes", &C::descriptor_bytes, "bytes",
            "descriptor shipped with a feature (32: 256-bit rBRIEF; 0: positions only)",
            field_bytes),
      field("imu_samples_per_frame", &C::imu_samples_per_frame, "",
            "IMU samples per camera frame (EuRoC: 200 Hz / 20 Hz)", samples),
      field("imu_sample_bytes", &C::imu_sample_bytes, "bytes",
            "one IMU sample: time stamp + 3 gyro + 3 accel doubles", field_bytes),
      field("gps_samples_per_frame", &C::gps_samples_per_frame, "",
            "GPS fixes per frame that has GPS (assumed 1)", samples),
      field("gps_sample_bytes", &C::gps_sample_bytes, "bytes",
            "one GPS fix: time stamp + 3 position doubles", field_bytes),
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

nlohmann::json FrameTransfers::to_json() const {
  return {
      {"frame_id", frame_id},   {"features", features},   {"frontend_bytes", frontend_bytes},
      {"imu_bytes", imu_bytes}, {"gps_bytes", gps_bytes}, {"frontend_to_host", frontend_to_host()}};
}

KernelTransfer kernel_transfer(const trace::KernelRecord& k, const FrameTransferConfig& c,
                               const KernelMatrixFormat& format) {
  if (k.m < 0 || k.n < 0 || k.k < 0) {
    throw std::runtime_error(fmt::format("kernel '{}': expected sizes m, n, k >= 0, got {}, {}, {}",
                                         k.kernel, k.m, k.n, k.k));
  }
  KernelTransfer t;
  t.kernel = k.kernel;
  const KernelOperands operands =
      accelerable_kernel(k.kernel).operands(k, format, c.pack_symmetric);
  for (const auto& [name, bytes] : operands.inputs.items()) {
    t.input_bytes += bytes.get<std::int64_t>();
  }
  for (const auto& [name, bytes] : operands.outputs.items()) {
    t.output_bytes += bytes.get<std::int64_t>();
  }
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

sim::Time kernel_transfer_time(const Link& link, const KernelTransfer& kernel) {
  return link.transfer_time(kernel.input_bytes) + link.transfer_time(kernel.output_bytes);
}

}  // namespace edx::arch
