#include "arch/cost/energy_activity.hpp"

#include <fmt/format.h>

#include <stdexcept>

namespace edx::arch::cost {
namespace {

void require(bool ok, const char* field, const char* expected) {
  if (!ok) throw std::runtime_error(fmt::format("activity.{}: expected {}", field, expected));
}

}  // namespace

void FrameActivity::validate() const {
  require(frame_s > 0, "frame_s", "a frame time > 0 s");
  require(host_busy_s >= 0 && host_busy_s <= frame_s, "host_busy_s", "a time in [0, frame_s]");
  require(int8_ops >= 0, "int8_ops", "a count >= 0");
  require(fixed_macs >= 0, "fixed_macs", "a count >= 0");
  require(single_macs >= 0, "single_macs", "a count >= 0");
  require(double_macs >= 0, "double_macs", "a count >= 0");
  require(bram_bytes >= 0, "bram_bytes", "a count >= 0");
  require(dram_bytes >= 0, "dram_bytes", "a count >= 0");
  require(link_bytes >= 0, "link_bytes", "a count >= 0");
}

nlohmann::json FrameActivity::to_json() const {
  return {{"frame_s", frame_s},           {"host_busy_s", host_busy_s},
          {"fpga_present", fpga_present}, {"int8_ops", int8_ops},
          {"fixed_macs", fixed_macs},     {"single_macs", single_macs},
          {"double_macs", double_macs},   {"bram_bytes", bram_bytes},
          {"dram_bytes", dram_bytes},     {"link_bytes", link_bytes}};
}

}  // namespace edx::arch::cost
