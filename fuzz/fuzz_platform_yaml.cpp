// Fuzzes the platform YAML loader (arch/platform/platform.hpp): any text is a platform or a
// std::exception.
#include <exception>

#include "arch/platform/platform.hpp"
#include "fuzz/fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const edx::arch::Platform p =
        edx::arch::Platform::parse(std::string(edx::fuzz::as_text(data, size)), "fuzz.yaml");
    (void)p.to_json().dump();
  } catch (const std::exception&) {
  }
  return 0;
}
