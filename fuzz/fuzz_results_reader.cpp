// Fuzzes the results-database reader (reports/results_reader.hpp) on arbitrary SQLite bytes.
#include <exception>

#include "fuzz/fuzz_input.hpp"
#include "reports/results_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::filesystem::path file = edx::fuzz::scratch_dir() / "results.db";
  edx::fuzz::write_bytes(file, edx::fuzz::as_text(data, size));
  try {
    (void)edx::reports::read_results(file);
  } catch (const std::exception&) {
  }
  return 0;
}
