#include "arch/frontend/frontend_config.hpp"

#include "arch/common/yaml_fields.hpp"

namespace edx::arch {
const FieldList<FrontendConfig>& FrontendConfig::fields() {
  using C = FrontendConfig;
  const Bounds count = Bounds::at_least(1);
  const Bounds rate = Bounds::above(0);
  const Bounds bytes = Bounds::at_least(1);
  static const FieldList<C> list = {
      field("clock_mhz", &C::clock_mhz, "MHz", "frontend clock", Bounds::above(0).at_most(1000)),
      field("fe_pixels_per_cycle", &C::fe_pixels_per_cycle, "pixels/cycle",
            "pyramid pixels FD and IF each consume a cycle", rate),
      field("fd_stencil", &C::fd_stencil, "pixels",
            "FAST window side (Bresenham circle of radius 3: 7)", Bounds::at_least(3).odd_only()),
      field("if_stencil", &C::if_stencil, "pixels",
            "Gaussian kernel side (the trace's IF window_size wins)", count.odd_only()),
      field("fc_patch", &C::fc_patch, "pixels",
            "rBRIEF patch side (the trace's FC window_size wins)", Bounds::at_least(3).odd_only()),
      field("fc_patch_rows_per_cycle", &C::fc_patch_rows_per_cycle, "rows/cycle",
            "orientation: patch rows of moments a cycle", count),
      field("fc_tests_per_cycle", &C::fc_tests_per_cycle, "tests/cycle",
            "rBRIEF intensity tests a cycle (256 per descriptor)", count),
      field("mo_comparators", &C::mo_comparators, "", "256-bit Hamming-distance units of MO",
            count),
      field("dr_pixels_per_cycle", &C::dr_pixels_per_cycle, "pixels/cycle",
            "each image's level 0 streamed through DR's buffers", rate),
      field("dr_sad_units", &C::dr_sad_units, "", "window SADs DR computes in parallel", count),
      field("dc_pixels_per_cycle", &C::dc_pixels_per_cycle, "pixels/cycle",
            "derivative (Scharr) stencil over the LK pyramid", rate),
      field("dc_stencil", &C::dc_stencil, "pixels", "Scharr kernel side", count.odd_only()),
      field("lss_macs_per_cycle", &C::lss_macs_per_cycle, "MACs/cycle",
            "multiply-accumulates a cycle of the LK solver", count),
      field("pipeline_fe_sm", &C::pipeline_fe_sm, "",
            "FE of frame t+1 overlaps SM of frame t (double buffers)"),
      field("frame_interval_ms", &C::frame_interval_ms, "ms",
            "camera period of the frontend study; 0: frames back to back", Bounds::at_least(0)),
      field("bytes_per_pixel", &C::bytes_per_pixel, "bytes", "input pixel (8-bit grayscale: 1)",
            bytes.at_most(4)),
      choice_field("input_buffering", &C::input_buffering, "", {"on_chip_double", "dram"},
                   "where input images wait: double-buffered on chip (Sec. V-A) or in DRAM"),
      field("sb_optimization", &C::sb_optimization, "",
            "Sec. V-C: DR gets its own SB and re-reads its pixels when they would outlive FD/IF's"),
      choice_field("dr_reread", &C::dr_reread, "", {"on_chip_frame", "dram"},
                   "where that re-read comes from (dram: the paper's Sec. V-C wording)"),
      field("dr_window", &C::dr_window, "pixels",
            "DR block-matching window side (the trace's DR row wins)", count.odd_only()),
      field("dr_search", &C::dr_search, "offsets",
            "DR candidate offsets along the row (the trace's row wins)", count),
      field("pyramid_filter", &C::pyramid_filter, "pixels",
            "pyrDown's Gaussian side (DC builds the LK pyramid with it)", count.odd_only()),
      field("keypoint_bytes", &C::keypoint_bytes, "bytes",
            "keypoint entry in a FIFO/SPM: x, y, score, level, angle", bytes),
      field("descriptor_bytes", &C::descriptor_bytes, "bytes", "256-bit rBRIEF descriptor", bytes),
      field("match_bytes", &C::match_bytes, "bytes",
            "MO -> DR entry: left index, right index, distance", bytes),
      field("track_bytes", &C::track_bytes, "bytes",
            "LSS entry: id + previous and current position", bytes),
  };
  return list;
}

void FrontendConfig::validate() const { check_fields(*this, "frontend", fields()); }

nlohmann::json FrontendConfig::to_json() const { return fields_to_json(*this, fields()); }

FrontendConfig FrontendConfig::from_yaml(const YAML::Node& node, const std::string& where) {
  return parse_section<FrontendConfig>(node, where, "frontend");
}

}  // namespace edx::arch
