#pragma once
// The configured frontend accelerator (paper Sec. V, Fig. 11): its units, one per task of the
// graph, as instances of registered unit kinds (frontend_unit.hpp, arch/frontend/units/), and
// what they share: the clock, the FE input stream's rate, the stencil sizes its stencil buffers
// serve (the algorithm's), the memories' formats and how frames are fed. Parsed from the
// `frontend:` section of a platform YAML (docs/MODEL.md lists every field with its source);
// every field has a default, unknown keys are errors.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "arch/frontend/frontend_unit.hpp"
#include "common/config_fields.hpp"
#include "workloads/trace/records.hpp"

namespace YAML {
class Node;
}

namespace edx::arch {

struct FrontendConfig {
  double clock_mhz = 150.0;  ///< frontend clock
  /// The feature-extraction engine's input stream (one SB feeds FD and IF, Sec. V-C, Fig. 12):
  /// pyramid pixels FD and IF each consume a cycle.
  double fe_pixels_per_cycle = 2.0;
  // Stencil sizes: the algorithm's (Sec. V-C: "the window size of each stencil operation"),
  // which size the stencil buffers; a trace row's window_size wins where it records one.
  int fd_stencil = 7;  ///< FAST: Bresenham circle of radius 3 in a 7x7 window
  int if_stencil = 7;  ///< Gaussian kernel side (the trace's IF window_size wins)
  int fc_patch = 31;   ///< rBRIEF patch side (the trace's FC window_size wins)
  int dc_stencil = 3;  ///< Scharr kernel side
  // Frames.
  bool pipeline_fe_sm = true;      ///< FE of frame t+1 overlaps SM of frame t (double buffers)
  double frame_interval_ms = 0.0;  ///< camera period; 0: frames back to back
  int bytes_per_pixel = 1;         ///< 8-bit grayscale
  // Memories.
  /// Where the input images wait for the frontend: "on_chip_double" (the left and right images
  /// of two frames in on-chip buffers, paper Sec. V-A: "double-buffered on-chip"; DRAM is read
  /// once, by the DMA) or "dram" (every task stream that reads a raw image reads it from DRAM).
  std::string input_buffering = "on_chip_double";
  /// Sec. V-C: when DR's pixels would outlive FD/IF's SB, give DR its own SB and re-read them.
  bool sb_optimization = true;
  /// Where that re-read comes from: "on_chip_frame" (the on-chip input buffer; the physically
  /// consistent reading when the frames are on chip) or "dram" (the paper's Sec. V-C wording).
  /// With input_buffering: dram the re-read is from DRAM either way.
  std::string dr_reread = "on_chip_frame";
  int dr_window = 11;         ///< DR block-matching window side (the trace's DR row wins)
  int dr_search = 11;         ///< DR candidate offsets along the row (the trace's row wins)
  int pyramid_filter = 5;     ///< pyrDown's Gaussian side (DC builds the LK pyramid with it)
  int keypoint_bytes = 8;     ///< x, y (Q12.4), score, level, angle in a FIFO/SPM entry
  int descriptor_bytes = 32;  ///< 256-bit rBRIEF
  int match_bytes = 8;        ///< MO -> DR: left index, right index, Hamming distance
  int track_bytes = 12;       ///< LSS: id + previous and current position
  /// The units, one per task in trace::kTasks order: paper_frontend_units(), then what
  /// `frontend.units` lists over them by task name (a unit's keys overridden, its kind kept
  /// unless given).
  std::vector<FrontendUnitInstance> units = paper_frontend_units();

  /// The instance serving `task`.
  const FrontendUnitInstance& unit(trace::Task task) const;
  /// An instance's clock: its own, else clock_mhz.
  double clock_of(const FrontendUnitInstance& unit) const;
  /// The seven units of the paper's frontend (Sec. V), each kind at its defaults (Edx-Car's
  /// datapath): FD fast, IF gaussian, FC rbrief, MO hamming, DR sad_disparity, DC
  /// scharr_pyramid, LSS lk_solver.
  static std::vector<FrontendUnitInstance> paper_frontend_units();

  /// The keys of `frontend:` besides `units` (docs/CONFIG.md).
  static const FieldList<FrontendConfig>& fields();
  /// Every key of `frontend:`, `frontend.units.<task>` and each registered unit kind.
  static std::vector<ReferenceRow> reference();
  /// Throws std::runtime_error naming the field and the accepted range; every task has one unit
  /// whose kind runs it.
  void validate() const;
  nlohmann::json to_json() const;
  /// Reads the fields present in `node` (a map) over the defaults; `where` (file name) prefixes
  /// errors, which name the key and line: "car.yaml:12: frontend.clock_mhz: expected a number > 0".
  static FrontendConfig from_yaml(const YAML::Node& node, const std::string& where);
};

}  // namespace edx::arch
