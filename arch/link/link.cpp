#include "arch/link/link.hpp"

namespace edx::arch {

const char* to_string(Direction direction) {
  return direction == Direction::HostToFpga ? "host_to_fpga" : "fpga_to_host";
}

}  // namespace edx::arch
