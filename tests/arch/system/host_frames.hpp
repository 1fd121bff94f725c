#pragma once
// Hand-built CPU-baseline frames for the whole-system DES tests (system_des_test,
// attribution_test): each frame's frontend and backend thread work, run on a given number of
// cores.
#include <cstdint>
#include <vector>

#include "arch/platform/platform.hpp"
#include "arch/system/system_des.hpp"

namespace edx::arch {

/// n baseline frames: the frontend thread works `fe_ms`, the backend thread `be_ms`.
inline std::vector<SystemFrameWork> host_frames(std::size_t n, double fe_ms, double be_ms) {
  std::vector<SystemFrameWork> work(n);
  for (std::size_t f = 0; f < n; ++f) {
    work[f].frame_id = static_cast<std::int64_t>(f);
    work[f].frontend_host_ms = fe_ms;
    work[f].backend_host_ms = be_ms;
  }
  return work;
}

/// The CPU baseline variant of `work` on `cores` cores (streamed unless `isolated`).
inline SystemRun run_baseline(const std::vector<SystemFrameWork>& work, const SystemConfig& system,
                              int cores, bool isolated = false) {
  return run_system(work, FrontendConfig{}, *fpga_matrix_units(), *Platform{}.link, cores, system,
                    /*accelerated=*/false, isolated);
}

}  // namespace edx::arch
