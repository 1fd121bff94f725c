#include "arch/frontend/memory_plan.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "common/input_error.hpp"
#include "sim_core/clock.hpp"

namespace edx::arch {
namespace {

using trace::Image;
using trace::Task;

/// Largest value of `field` over the rows of (task, image) in all frames.
template <class Field>
std::int64_t max_over(const std::vector<trace::FrameTrace>& frames, Task task, Image image,
                      Field field) {
  std::int64_t best = 0;
  for (const trace::FrameTrace& f : frames) {
    for (const trace::TaskRecord& t : f.tasks) {
      if (t.task == task && t.image == image) best = std::max(best, field(t));
    }
  }
  return best;
}

/// The per-level shapes of the first row of (task, image) that has them.
std::vector<trace::LevelWork> levels_of(const std::vector<trace::FrameTrace>& frames, Task task,
                                        Image image) {
  for (const trace::FrameTrace& f : frames) {
    for (const trace::TaskRecord& t : f.tasks) {
      if (t.task == task && t.image == image && !t.per_level.empty()) return t.per_level;
    }
  }
  return {};
}

/// A rate as an exact fraction pixels/cycles (1/1024 resolution is exact for the configured
/// rates, which are multiples of 1/1024 or rounded to them).
PixelStream stream(std::int64_t first_cycle, double pixels_per_cycle) {
  constexpr std::int64_t kDenominator = 1024;
  return {first_cycle, std::max<std::int64_t>(1, std::llround(pixels_per_cycle * kDenominator)),
          kDenominator};
}

/// Cycles until a window of side k centred on a pixel has been streamed: ((k-1)/2 lines +
/// (k-1)/2 pixels) at `rate` pixels a cycle.
std::int64_t window_lag_cycles(int k, std::int64_t width, double rate) {
  const std::int64_t half = (k - 1) / 2;
  return static_cast<std::int64_t>(std::ceil(static_cast<double>(half * width + half) / rate));
}

/// A window of `side` pixels over the `width`-pixel lines of stencil buffer `buffer`: a side
/// wider than the lines that is the platform's (`configured`, not the trace's) is an error naming
/// its key, placed at the platform file by simulate_system (issue 45).
void require_window_fits(int side, int configured, const char* key, std::int64_t width,
                         const std::string& buffer) {
  if (side > width && side == configured) {
    throw InputError({}, key,
                     fmt::format("a {}-pixel window is wider than the {}-pixel lines of stencil "
                                 "buffer {} (a pyramid level of the trace's images)",
                                 side, width, buffer));
  }
}

const TaskSpan& span_of(const FrontendFrameTiming& t, Task task, Image image) {
  for (const TaskSpan& s : t.tasks) {
    if (s.task == task && s.image == image) return s;
  }
  throw std::runtime_error(fmt::format("frame {}: no {} {} timing", t.frame_id,
                                       trace::to_string(task), trace::to_string(image)));
}

int window_of(const std::vector<trace::FrameTrace>& frames, Task task, Image image, int configured,
              bool search) {
  const std::int64_t v = max_over(frames, task, image, [&](const trace::TaskRecord& r) {
    return search ? r.search_range : r.window_size;
  });
  return v > 0 ? static_cast<int>(v) : configured;
}

}  // namespace

nlohmann::json FrontendMemoryPlan::to_json() const {
  nlohmann::json sbs = nlohmann::json::array();
  for (const StencilBuffer& sb : stencil_buffers) {
    sbs.push_back({{"name", sb.spec.name},
                   {"lines", sb.lines},
                   {"line_pixels", sb.fifo_depth_pixels},
                   {"fifo_bytes", sb.fifo_bytes},
                   {"shift_register_bytes", sb.shift_register_bytes}});
  }
  // Each FIFO's and the SPM's mapping of one copy, as the memory kind mapped it (bram).
  const auto with_mapping = [this](nlohmann::json j, const MemoryStructure& s) {
    for (const StructureUsage& u : bram.structures) {
      if (u.structure.name == s.name) j["mapping"] = u.mapping.to_json();
    }
    return j;
  };
  nlohmann::json fifo_list = nlohmann::json::array();
  for (const FifoSizing& f : fifos) fifo_list.push_back(with_mapping(f.to_json(), f.structure));
  return {{"stencil_buffers", sbs},
          {"fifos", fifo_list},
          {"scratchpad", with_mapping(scratchpad.to_json(), scratchpad.structure)},
          {"dr_left", dr_left.to_json()},
          {"dr_right", dr_right.to_json()},
          {"sb_optimization", sb_optimization},
          {"sb_bytes", sb_bytes},
          {"sb_bytes_without_optimization", sb_bytes_without_optimization},
          {"sb_bytes_without_optimization_bound", sb_bytes_without_optimization_bound},
          {"fifo_bytes", fifo_bytes},
          {"spm_bytes", spm_bytes},
          {"input_buffer_bytes", input_buffer_bytes},
          {"dram_bytes_per_frame", dram_bytes_per_frame},
          {"extra_dram_bytes_per_frame", extra_dram_bytes_per_frame},
          // The paper's units (Sec. VII-B "On-chip Memory Design": SB 0.4 MB, SPM 3.6 MB, "+9 MB"
          // without the SB optimization), MB = 10^6 bytes.
          {"sb_mb", 1e-6 * static_cast<double>(sb_bytes)},
          {"spm_mb", 1e-6 * static_cast<double>(spm_bytes)},
          {"input_buffer_mb", 1e-6 * static_cast<double>(input_buffer_bytes)},
          {"sb_added_without_optimization_mb",
           1e-6 * static_cast<double>(sb_bytes_without_optimization - sb_bytes)},
          {"sb_added_without_optimization_bound_mb",
           1e-6 * static_cast<double>(sb_bytes_without_optimization_bound - sb_bytes)},
          {"bram", bram.to_json()}};
}

FrontendMemoryPlan plan_frontend_memory(const std::vector<trace::FrameTrace>& frames,
                                        const FrontendSimResult& timing, int width, int height,
                                        const FrontendConfig& c, const Device& device,
                                        const OnChipMemory& memory) {
  if (frames.empty() || timing.frames.size() != frames.size()) {
    throw std::runtime_error("frontend memory plan: the timing must cover the trace's frames");
  }
  FrontendMemoryPlan plan;
  plan.sb_optimization = c.sb_optimization;
  const int b = c.bytes_per_pixel;

  // Stencil buffers, one per pyramid level stream (levels are produced concurrently).
  const int if_side = window_of(frames, Task::IF, Image::Left, c.if_stencil, false);
  const int fc_side = window_of(frames, Task::FC, Image::Left, c.fc_patch, false);
  for (const trace::LevelWork& level : levels_of(frames, Task::FD, Image::Left)) {
    const std::string name = fmt::format("fe.L{}", level.level);
    require_window_fits(c.fd_stencil, c.fd_stencil, "frontend.fd_stencil", level.width, name);
    require_window_fits(if_side, c.if_stencil, "frontend.if_stencil", level.width, name);
    plan.stencil_buffers.push_back(
        size_stencil_buffer({fmt::format("fe.L{}", level.level),
                             level.width,
                             b,
                             {{"FD", c.fd_stencil, c.fd_stencil}, {"IF", if_side, if_side}}}));
  }
  for (const trace::LevelWork& level : levels_of(frames, Task::IF, Image::Left)) {
    require_window_fits(fc_side, c.fc_patch, "frontend.fc_patch", level.width,
                        fmt::format("fc.L{}", level.level));
    plan.stencil_buffers.push_back(size_stencil_buffer(
        {fmt::format("fc.L{}", level.level), level.width, b, {{"FC", fc_side, fc_side}}}));
  }
  const std::vector<trace::LevelWork> lk_levels = levels_of(frames, Task::DC, Image::Left);
  for (const trace::LevelWork& level : lk_levels) {
    const std::string name = fmt::format("dc.L{}", level.level);
    require_window_fits(c.dc_stencil, c.dc_stencil, "frontend.dc_stencil", level.width, name);
    require_window_fits(c.pyramid_filter, c.pyramid_filter, "frontend.pyramid_filter", level.width,
                        name);
    plan.stencil_buffers.push_back(size_stencil_buffer(
        {fmt::format("dc.L{}", level.level),
         level.width,
         b,
         {{"DC", c.dc_stencil, c.dc_stencil}, {"pyrDown", c.pyramid_filter, c.pyramid_filter}}}));
  }
  const int dr_window = window_of(frames, Task::DR, Image::Stereo, c.dr_window, false);
  const int dr_search = window_of(frames, Task::DR, Image::Stereo, c.dr_search, true);
  require_window_fits(dr_window, c.dr_window, "frontend.dr_window", width, "dr.left");
  const StencilBuffer dr_left =
      size_stencil_buffer({"dr.left", width, b, {{"DR", dr_window, dr_window}}});
  const StencilBuffer dr_right =
      size_stencil_buffer({"dr.right", width, b, {{"DR", dr_window, dr_window + dr_search - 1}}});

  // The SB decision for DR's reads, from the DES stream timings: P1 = FD/IF's read of level 0,
  // C1 = FD/IF's use (its window lag later), C2 = DR's use, P2 = DR's re-read (its lag earlier).
  const sim::ClockDomain clock("frontend", c.clock_mhz);
  const std::int64_t pixels = static_cast<std::int64_t>(width) * height;
  const auto cycle = [&](sim::Time t) { return static_cast<std::int64_t>(clock.cycles_in(t)); };
  const std::int64_t fe_lag =
      window_lag_cycles(std::max(c.fd_stencil, if_side), width, c.fe_pixels_per_cycle);
  // DR streams its images at its unit's rate (Sec. V-C: its SB's production and consumption).
  const double dr_rate = c.unit(Task::DR).unit->stream_pixels_per_cycle(c);
  const std::int64_t dr_lag = window_lag_cycles(dr_window, width, dr_rate);
  const auto decide = [&](const FrontendFrameTiming& t, Image image) {
    const std::int64_t read = cycle(span_of(t, Task::FD, image).start);
    const std::int64_t dr = cycle(span_of(t, Task::DR, Image::Stereo).start);
    return decide_sb_sharing(stream(read, c.fe_pixels_per_cycle),
                             stream(read + fe_lag, c.fe_pixels_per_cycle),
                             stream(dr + dr_lag, dr_rate), stream(dr, dr_rate), pixels, b);
  };
  for (const FrontendFrameTiming& t : timing.frames) {
    if (span_of(t, Task::DR, Image::Stereo).end == span_of(t, Task::DR, Image::Stereo).start) {
      continue;  // DR did not run (no matches): nothing to keep
    }
    const SbSharingDecision left = decide(t, Image::Left);
    const SbSharingDecision right = decide(t, Image::Right);
    if (left.shared_pixels > plan.dr_left.shared_pixels) plan.dr_left = left;
    if (right.shared_pixels > plan.dr_right.shared_pixels) plan.dr_right = right;
  }

  std::int64_t other_sb_bytes = 0;
  for (const StencilBuffer& sb : plan.stencil_buffers) other_sb_bytes += sb.fifo_bytes;
  // Shared: DR keeps its pixels in FD/IF's level-0 SB for their whole lifetime. The paper's rule
  // sizes that by lifetime x rate; a FIFO never holds more than the images in flight.
  const std::int64_t frames_in_flight = c.pipeline_fe_sm ? 2 : 1;
  const std::int64_t shared_pixels = plan.dr_left.shared_pixels + plan.dr_right.shared_pixels;
  const std::int64_t bounded_pixels =
      std::min(plan.dr_left.shared_pixels, frames_in_flight * pixels) +
      std::min(plan.dr_right.shared_pixels, frames_in_flight * pixels);
  plan.sb_bytes_without_optimization = other_sb_bytes + shared_pixels * b;
  plan.sb_bytes_without_optimization_bound = other_sb_bytes + bounded_pixels * b;
  const bool replicate = c.sb_optimization && plan.dr_left.replicate && plan.dr_right.replicate;
  const bool on_chip_input = c.input_buffering == "on_chip_double";
  const bool reread_from_dram = !on_chip_input || c.dr_reread == "dram";
  const std::int64_t image_bytes = pixels * b;
  std::vector<MemoryStructure> structures;
  if (replicate) {
    plan.stencil_buffers.push_back(dr_left);
    plan.stencil_buffers.push_back(dr_right);
    plan.sb_bytes = other_sb_bytes + dr_left.fifo_bytes + dr_right.fifo_bytes;
    if (reread_from_dram) {
      plan.extra_dram_bytes_per_frame =
          plan.dr_left.extra_dram_bytes_per_frame + plan.dr_right.extra_dram_bytes_per_frame;
    }
  } else {
    plan.sb_bytes = plan.sb_bytes_without_optimization;
    structures.push_back({"dr.shared_lifetime", 8 * std::int64_t{b}, shared_pixels, 1});
  }
  // Input images: read from DRAM once a frame (left and right); without the on-chip buffer, DC
  // streams the left image from DRAM again to build the LK pyramid.
  if (on_chip_input) {
    plan.input_buffer_bytes = 2 * 2 * image_bytes;  // two frames, left and right (in the SPM)
  } else {
    plan.extra_dram_bytes_per_frame += image_bytes;
  }
  plan.dram_bytes_per_frame = 2 * image_bytes + plan.extra_dram_bytes_per_frame;
  for (const StencilBuffer& sb : plan.stencil_buffers) {
    for (const MemoryStructure& s : sb.memory_structures()) structures.push_back(s);
  }

  // FIFOs for the lists streamed from one task to the next.
  const auto count = [&](Task task, Image image, auto field) {
    return std::max<std::int64_t>(1, max_over(frames, task, image, field));
  };
  const auto descriptors = [](const trace::TaskRecord& r) { return r.descriptors; };
  const auto keypoints = [](const trace::TaskRecord& r) { return r.keypoints; };
  const auto points = [](const trace::TaskRecord& r) { return r.points; };
  plan.fifos.push_back(size_fifo({"fd_to_fc",
                                  std::max(count(Task::FC, Image::Left, descriptors),
                                           count(Task::FC, Image::Right, descriptors)),
                                  c.keypoint_bytes}));
  plan.fifos.push_back(
      size_fifo({"mo_to_dr", count(Task::DR, Image::Stereo, keypoints), c.match_bytes}));
  plan.fifos.push_back(
      size_fifo({"lss_tracks", count(Task::DC, Image::Left, points), c.track_bytes}));
  for (const FifoSizing& f : plan.fifos) {
    plan.fifo_bytes += f.bytes;
    structures.push_back(f.structure);
  }

  // Scratchpad: what LSS and MO read at arbitrary positions.
  std::int64_t lk_pyramid = 0, lk_level0 = 0;
  for (const trace::LevelWork& level : lk_levels) {
    lk_pyramid += level.pixels * b;
    if (level.level == 0) lk_level0 = level.pixels * b;
  }
  ScratchpadSpec spm;
  spm.name = "frontend_spm";
  // Every on-chip memory is an SB, a FIFO or the SPM (the paper's three kinds, Sec. V-C); the
  // double-buffered input images are neither a stencil nor a queue: SPM regions.
  spm.regions = {
      {"input_frames", plan.input_buffer_bytes},
      // With the input on chip, level 0 of the previous and of the current LK pyramid are the
      // left images of the two buffered frames (LSS of frame t+1 reads frame t's as its
      // previous image): the SPM holds only the levels above.
      {"lk_pyramid_previous", on_chip_input ? lk_pyramid - lk_level0 : lk_pyramid},
      {"lk_pyramid_current", on_chip_input ? lk_pyramid - lk_level0 : lk_pyramid},
      {"previous_features", count(Task::DC, Image::Left, points) * c.keypoint_bytes},
      {"keypoints_left", count(Task::FC, Image::Left, descriptors) * c.keypoint_bytes},
      {"keypoints_right", count(Task::FC, Image::Right, descriptors) * c.keypoint_bytes},
      {"descriptors_left", count(Task::FC, Image::Left, descriptors) * c.descriptor_bytes},
      {"descriptors_right", count(Task::FC, Image::Right, descriptors) * c.descriptor_bytes},
  };
  plan.scratchpad = size_scratchpad(spm);
  plan.spm_bytes = plan.scratchpad.bytes;
  structures.push_back(plan.scratchpad.structure);

  plan.bram = check_bram("frontend", structures, device, memory);
  return plan;
}

}  // namespace edx::arch
