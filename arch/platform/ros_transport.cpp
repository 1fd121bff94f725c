#include "arch/platform/ros_transport.hpp"

#include "common/yaml_fields.hpp"

namespace edx::arch {

namespace {
/// A pose message: a stamp and 7 doubles (position and quaternion), plus a header's frame id.
constexpr double kPoseBytes = 8 + 7 * 8 + 16;
}  // namespace

RosTransport::FrameCost RosTransport::frame_cost(const trace::FrameTrace& frame,
                                                 const FrameTransferConfig& transfers, int width,
                                                 int height) const {
  FrameCost c;
  if (!enabled) return c;
  const auto message = [this](double bytes) { return message_ms + bytes * byte_ns * 1e-6; };
  const double image = static_cast<double>(width) * height * image_bytes_per_pixel;
  c.frontend_ms = 2 * message(image);
  const FrameTransfers t = frontend_transfer(frame, transfers);
  c.backend_ms = message(static_cast<double>(t.frontend_bytes)) + message(kPoseBytes);
  for (int i = 0; i < transfers.imu_samples_per_frame; ++i) {
    c.backend_ms += message(transfers.imu_sample_bytes);
  }
  if (t.gps_bytes > 0) {
    for (int i = 0; i < transfers.gps_samples_per_frame; ++i) {
      c.backend_ms += message(transfers.gps_sample_bytes);
    }
  }
  return c;
}

const FieldList<RosTransport>& RosTransport::fields() {
  using C = RosTransport;
  static const FieldList<C> list = {
      field("enabled", &C::enabled, "",
            "run the CPU baseline's pipeline as ROS 1 nodes (the paper's w/ ROS rows)"),
      field("message_ms", &C::message_ms, "ms",
            "fixed cost of a message (TZC, IROS 2019: the lower end of its hundreds of us)",
            Bounds::at_least(0).at_most(1000)),
      field("byte_ns", &C::byte_ns, "ns/byte",
            "cost of a payload byte (TZC: tens of ms for 4 MB; the lower end, 10 ms / 4 MiB)",
            Bounds::at_least(0).at_most(1e6)),
      field("image_bytes_per_pixel", &C::image_bytes_per_pixel, "bytes",
            "bytes of an image message's pixel (mono8: 1)", Bounds::at_least(1).at_most(16)),
  };
  return list;
}

void RosTransport::validate() const { check_fields(*this, "ros", fields()); }

nlohmann::json RosTransport::to_json() const { return fields_to_json(*this, fields()); }

RosTransport RosTransport::from_yaml(const YAML::Node& node, const std::string& where) {
  return parse_section<RosTransport>(node, where, "ros");
}

}  // namespace edx::arch
