// Fuzzes the sweep-spec parser (arch/sweep/sweep.hpp) with a valid base platform beside it
// (base.yaml, written once), and enumerates a few points of what parses.
#include <exception>

#include "arch/sweep/sweep.hpp"
#include "fuzz/fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const bool base_written = [] {
    edx::fuzz::write_bytes(edx::fuzz::scratch_dir() / "base.yaml",
                           "name: base\nbackend: {units: {gemm: {block: 2}}}\n");
    return true;
  }();
  (void)base_written;
  try {
    const edx::arch::SweepSpec spec = edx::arch::SweepSpec::parse(
        std::string(edx::fuzz::as_text(data, size)), "fuzz.yaml", edx::fuzz::scratch_dir());
    const edx::arch::SweepPoints points(spec);
    for (std::size_t i = 0; i < points.size() && i < 3; ++i) {
      (void)edx::arch::sweep_platform(spec, points.at(i));
    }
  } catch (const std::exception&) {
  }
  return 0;
}
