// Fuzzes the trace reader (workloads/trace/reader.hpp) on arbitrary SQLite file bytes.
#include <exception>

#include "fuzz/fuzz_input.hpp"
#include "workloads/trace/reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::filesystem::path file = edx::fuzz::scratch_dir() / "trace.db";
  edx::fuzz::write_bytes(file, edx::fuzz::as_text(data, size));
  try {
    const edx::trace::TraceReader reader(file);
    (void)reader.read_all();
  } catch (const std::exception&) {
  }
  return 0;
}
