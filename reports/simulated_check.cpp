#include "reports/simulated_check.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <atomic>
#include <stdexcept>

#include "arch/results/results_db.hpp"
#include "arch/system/result_rows.hpp"
#include "arch/system/system_model.hpp"
#include "common/resources.hpp"
#include "reports/metrics.hpp"
#include "reports/results_reader.hpp"
#include "workloads/trace/reader.hpp"

namespace edx::reports {

SimulatedRun simulate_for_check(const arch::Platform& platform, const std::filesystem::path& trace,
                                const std::vector<ComparedBaseline>& baselines) {
  const trace::TraceReader reader(trace.string());
  const std::vector<trace::FrameTrace> frames = reader.read_all();
  const arch::SystemResult result =
      arch::simulate_system(platform, frames, reader.meta(), trace.string());
  static std::atomic<unsigned> counter{0};
  const std::filesystem::path scratch =
      std::filesystem::temp_directory_path() /
      fmt::format("edx-check-{}-{}.db", ::getpid(), counter.fetch_add(1));
  std::filesystem::remove(scratch);
  SimulatedRun out;
  try {
    const results::RunRows rows = arch::result_rows(result);
    arch::write_results(scratch, rows);
    for (const ComparedBaseline& b : baselines) {
      const arch::Platform other = arch::Platform::load(common::find_resource(b.config).string());
      if (other.name == platform.name) continue;  // this run is that baseline's
      arch::write_results(scratch, arch::result_rows(arch::simulate_system(
                                       other, frames, reader.meta(), trace.string())));
    }
    const ResultsData data = read_results(scratch);
    const RunData* r = data.find(rows.run.run_id);
    if (r == nullptr) throw std::logic_error("edx check: the simulated run is not in its database");
    out.metrics = run_metrics(*r);
    add_baseline_metrics(out.metrics, data, *r, baselines);
    out.run_id = r->run_id;
  } catch (...) {
    std::filesystem::remove(scratch);
    throw;
  }
  std::filesystem::remove(scratch);
  for (const char* suffix : {"-wal", "-shm"}) std::filesystem::remove(scratch.string() + suffix);
  out.metrics["frontend"] = result.frontend.to_json();
  return out;
}

}  // namespace edx::reports
