#pragma once
// The ROS 1 transport of a CPU baseline (`ros:`, docs/MODEL.md "ROS transport"; issue 41): the
// cost of the messages that cross the localization pipeline's node boundaries when its parts run
// as ROS nodes (the paper's "w/ ROS" baselines; its own framework runs without ROS, "about 4 %
// faster", Sec. IV). Off by default. Per frame, on the host:
//
//   frontend node, before its tasks:  2 image messages of W·H·bytes_per_pixel bytes
//   backend node, beside its work:    the IMU samples' messages, the GPS fix's (frames with GPS),
//                                     one features message (the frame's frontend results), one
//                                     pose message out
//   each message:  t = message_ms + bytes × byte_ns
//
// (message sizes from `transfers:`, the same records the FPGA link carries). The constants are
// readings of the TZC paper's ROS 1 measurements (Wang et al., "TZC: Efficient Inter-Process
// Communication for Robotics Middleware with Partial Serialization", IROS 2019,
// arXiv:1810.00556): a 4 MB message costs ROS's IPC "tens of milliseconds", of which what stays
// constant once the payload no longer crosses the socket is "hundreds of microseconds". edx
// takes the lower end of each: 10 ms / 4 MiB = 2.38 ns a byte, 0.1 ms a message.
#include <nlohmann/json.hpp>
#include <string>

#include "arch/link/frame_transfers.hpp"
#include "common/config_fields.hpp"
#include "workloads/trace/records.hpp"

namespace YAML {
class Node;
}

namespace edx::arch {

struct RosTransport {
  bool enabled = false;
  double message_ms = 0.1;            ///< fixed cost of a message (see the header)
  double byte_ns = 10e6 / 4194304.0;  ///< 10 ms / 4 MiB
  int image_bytes_per_pixel = 1;      ///< mono8 images

  /// A frame's ROS time on the host (ms): the frontend node's image messages, the backend
  /// node's other messages; both 0 when disabled.
  struct FrameCost {
    double frontend_ms = 0, backend_ms = 0;
  };
  FrameCost frame_cost(const trace::FrameTrace& frame, const FrameTransferConfig& transfers,
                       int width, int height) const;

  static const FieldList<RosTransport>& fields();
  void validate() const;
  nlohmann::json to_json() const;
  static RosTransport from_yaml(const YAML::Node& node, const std::string& where);
};

}  // namespace edx::arch
