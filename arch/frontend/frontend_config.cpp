#include "arch/frontend/frontend_config.hpp"

#include <fmt/format.h>

#include <stdexcept>

#include "arch/common/yaml_fields.hpp"

namespace edx::arch {
namespace {

void require(bool ok, const char* field, const std::string& expected) {
  if (!ok) throw std::runtime_error(fmt::format("frontend.{}: expected {}", field, expected));
}

}  // namespace

void FrontendConfig::validate() const {
  require(clock_mhz > 0 && clock_mhz <= 1000, "clock_mhz", "a frequency in (0, 1000] MHz");
  require(fe_pixels_per_cycle > 0, "fe_pixels_per_cycle", "a rate > 0");
  require(fd_stencil >= 3 && fd_stencil % 2 == 1, "fd_stencil", "an odd size >= 3");
  require(if_stencil >= 1 && if_stencil % 2 == 1, "if_stencil", "an odd size >= 1");
  require(fc_patch >= 3 && fc_patch % 2 == 1, "fc_patch", "an odd size >= 3");
  require(fc_patch_rows_per_cycle >= 1, "fc_patch_rows_per_cycle", "an integer >= 1");
  require(fc_tests_per_cycle >= 1, "fc_tests_per_cycle", "an integer >= 1");
  require(mo_comparators >= 1, "mo_comparators", "an integer >= 1");
  require(dr_pixels_per_cycle > 0, "dr_pixels_per_cycle", "a rate > 0");
  require(dr_sad_units >= 1, "dr_sad_units", "an integer >= 1");
  require(dc_pixels_per_cycle > 0, "dc_pixels_per_cycle", "a rate > 0");
  require(dc_stencil >= 1 && dc_stencil % 2 == 1, "dc_stencil", "an odd size >= 1");
  require(lss_macs_per_cycle >= 1, "lss_macs_per_cycle", "an integer >= 1");
  require(frame_interval_ms >= 0, "frame_interval_ms", "0 (back to back) or a period > 0");
  require(bytes_per_pixel >= 1 && bytes_per_pixel <= 4, "bytes_per_pixel", "1 to 4");
  require(dr_window >= 1 && dr_window % 2 == 1, "dr_window", "an odd size >= 1");
  require(dr_search >= 1, "dr_search", "an integer >= 1");
  require(pyramid_filter >= 1 && pyramid_filter % 2 == 1, "pyramid_filter", "an odd size >= 1");
  require(keypoint_bytes >= 1, "keypoint_bytes", "an integer >= 1");
  require(descriptor_bytes >= 1, "descriptor_bytes", "an integer >= 1");
  require(match_bytes >= 1, "match_bytes", "an integer >= 1");
  require(track_bytes >= 1, "track_bytes", "an integer >= 1");
  require(input_buffering == "on_chip_double" || input_buffering == "dram", "input_buffering",
          fmt::format("on_chip_double or dram, got '{}'", input_buffering));
  require(dr_reread == "on_chip_frame" || dr_reread == "dram", "dr_reread",
          fmt::format("on_chip_frame or dram, got '{}'", dr_reread));
}

nlohmann::json FrontendConfig::to_json() const {
  return {{"clock_mhz", clock_mhz},
          {"fe_pixels_per_cycle", fe_pixels_per_cycle},
          {"fd_stencil", fd_stencil},
          {"if_stencil", if_stencil},
          {"fc_patch", fc_patch},
          {"fc_patch_rows_per_cycle", fc_patch_rows_per_cycle},
          {"fc_tests_per_cycle", fc_tests_per_cycle},
          {"mo_comparators", mo_comparators},
          {"dr_pixels_per_cycle", dr_pixels_per_cycle},
          {"dr_sad_units", dr_sad_units},
          {"dc_pixels_per_cycle", dc_pixels_per_cycle},
          {"dc_stencil", dc_stencil},
          {"lss_macs_per_cycle", lss_macs_per_cycle},
          {"pipeline_fe_sm", pipeline_fe_sm},
          {"frame_interval_ms", frame_interval_ms},
          {"bytes_per_pixel", bytes_per_pixel},
          {"input_buffering", input_buffering},
          {"sb_optimization", sb_optimization},
          {"dr_reread", dr_reread},
          {"dr_window", dr_window},
          {"dr_search", dr_search},
          {"pyramid_filter", pyramid_filter},
          {"keypoint_bytes", keypoint_bytes},
          {"descriptor_bytes", descriptor_bytes},
          {"match_bytes", match_bytes},
          {"track_bytes", track_bytes}};
}

FrontendConfig FrontendConfig::from_yaml(const YAML::Node& node, const std::string& where) {
  FrontendConfig c;
  YamlFields f(node, where, "frontend");
  f.read("clock_mhz", c.clock_mhz, 0.0);
  f.read("fe_pixels_per_cycle", c.fe_pixels_per_cycle, 0.0);
  f.read("fd_stencil", c.fd_stencil, 3);
  f.read("if_stencil", c.if_stencil, 1);
  f.read("fc_patch", c.fc_patch, 3);
  f.read("fc_patch_rows_per_cycle", c.fc_patch_rows_per_cycle, 1);
  f.read("fc_tests_per_cycle", c.fc_tests_per_cycle, 1);
  f.read("mo_comparators", c.mo_comparators, 1);
  f.read("dr_pixels_per_cycle", c.dr_pixels_per_cycle, 0.0);
  f.read("dr_sad_units", c.dr_sad_units, 1);
  f.read("dc_pixels_per_cycle", c.dc_pixels_per_cycle, 0.0);
  f.read("dc_stencil", c.dc_stencil, 1);
  f.read("lss_macs_per_cycle", c.lss_macs_per_cycle, 1);
  f.read("pipeline_fe_sm", c.pipeline_fe_sm);
  f.read("frame_interval_ms", c.frame_interval_ms, -1e-12);
  f.read("bytes_per_pixel", c.bytes_per_pixel, 1);
  f.read("input_buffering", c.input_buffering);
  f.read("sb_optimization", c.sb_optimization);
  f.read("dr_reread", c.dr_reread);
  f.read("dr_window", c.dr_window, 1);
  f.read("dr_search", c.dr_search, 1);
  f.read("pyramid_filter", c.pyramid_filter, 1);
  f.read("keypoint_bytes", c.keypoint_bytes, 1);
  f.read("descriptor_bytes", c.descriptor_bytes, 1);
  f.read("match_bytes", c.match_bytes, 1);
  f.read("track_bytes", c.track_bytes, 1);
  f.finish();
  try {
    c.validate();
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    const std::string key = message.substr(9, message.find(':') - 9);  // after "frontend."
    f.fail(key, message.substr(message.find(':') + 2));
  }
  return c;
}

}  // namespace edx::arch
