#pragma once
// A simulated run as the rows of the results database (arch/results/schema.hpp): what
// `edx simulate --out` and sweeps store (docs/MODEL.md "Results database", docs/RESULTS.md).
#include "arch/results/schema.hpp"
#include "arch/system/system_model.hpp"

namespace edx::arch {

/// The rows of `result` in every run table; per_frame = false leaves out the frames and offload
/// rows (a sweep's points keep the summaries, latency, throughput, energy, schedule and
/// resources).
results::RunRows result_rows(const SystemResult& result, bool per_frame = true);

}  // namespace edx::arch
