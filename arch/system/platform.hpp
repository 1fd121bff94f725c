#pragma once
// A platform description (configs/*.yaml, docs/MODEL.md): the accelerator's configured
// datapath and memories, the links, and the host CPU, as plain structs parsed from YAML.
//
//   name: edx_car
//   description: ...
//   device: xc7v690t
//   host: {frontend_time_scale: 2.37, provenance: "..."}
//   frontend: {clock_mhz: 150, ...}
//   link: {preset: pcie3_x8, ...}
//   transfers: {scalar_bytes: 8, ...}
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "arch/frontend/frontend_config.hpp"
#include "arch/link/frame_transfers.hpp"
#include "arch/link/link.hpp"

namespace edx::arch {

/// The host CPU as far as the frontend comparison needs it: trace host times are scaled to the
/// target CPU by a declared factor (DESIGN.md, "Host CPU").
struct HostConfig {
  std::string name = "trace host";
  /// Target CPU time = trace host time x this factor, for the frontend tasks.
  double frontend_time_scale = 1.0;
  /// Where the factor comes from (measurement, datasheet ratio, or calibration against a paper
  /// figure: then say so).
  std::string provenance = "identity: the trace host is the target";
  nlohmann::json to_json() const;
};

struct Platform {
  std::string name;
  std::string description;
  std::string device = "xc7v690t";  ///< the FPGA (arch/memory/bram.hpp Device::by_name)
  HostConfig host;
  FrontendConfig frontend;
  LinkSpec link = LinkSpec::pcie3_x8();  ///< host <-> FPGA
  FrameTransferConfig transfers;         ///< what crosses the link per frame
  nlohmann::json to_json() const;

  /// Reads a platform YAML file; errors name the file, line and key (unknown keys included).
  static Platform load(const std::filesystem::path& path);
  /// Parses YAML text; `where` names it in errors.
  static Platform parse(const std::string& text, const std::string& where);
};

}  // namespace edx::arch
