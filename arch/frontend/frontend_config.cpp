#include "arch/frontend/frontend_config.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <map>
#include <stdexcept>

#include "arch/common/bounds.hpp"
#include "common/yaml_fields.hpp"

namespace edx::arch {
namespace {

/// Keys of `frontend:` before the units were instances (2026-11-28): where each went.
const std::map<std::string, std::string>& moved_keys() {
  static const std::map<std::string, std::string> moved = {
      {"fc_patch_rows_per_cycle", "frontend.units.FC.patch_rows_per_cycle"},
      {"fc_tests_per_cycle", "frontend.units.FC.tests_per_cycle"},
      {"mo_comparators", "frontend.units.MO.comparators"},
      {"dr_pixels_per_cycle", "frontend.units.DR.pixels_per_cycle"},
      {"dr_sad_units", "frontend.units.DR.sad_units"},
      {"dc_pixels_per_cycle", "frontend.units.DC.pixels_per_cycle"},
      {"lss_macs_per_cycle", "frontend.units.LSS.macs_per_cycle"},
  };
  return moved;
}

}  // namespace

std::vector<FrontendUnitInstance> FrontendConfig::paper_frontend_units() {
  using trace::Task;
  return {
      make_frontend_unit(Task::FD, "fast"),          make_frontend_unit(Task::IF, "gaussian"),
      make_frontend_unit(Task::FC, "rbrief"),        make_frontend_unit(Task::MO, "hamming"),
      make_frontend_unit(Task::DR, "sad_disparity"), make_frontend_unit(Task::DC, "scharr_pyramid"),
      make_frontend_unit(Task::LSS, "lk_solver")};
}

const FrontendUnitInstance& FrontendConfig::unit(trace::Task task) const {
  const std::size_t i = static_cast<std::size_t>(task);
  if (i < units.size() && units[i].name == trace::to_string(task)) return units[i];
  for (const FrontendUnitInstance& u : units) {
    if (u.name == trace::to_string(task)) return u;
  }
  throw std::runtime_error(fmt::format("frontend.units: no unit for {}", trace::to_string(task)));
}

double FrontendConfig::clock_of(const FrontendUnitInstance& unit) const {
  return unit.clock_mhz > 0 ? unit.clock_mhz : clock_mhz;
}
const FieldList<FrontendConfig>& FrontendConfig::fields() {
  using C = FrontendConfig;
  const Bounds count = Bounds::at_least(1);
  const Bounds window = bounds::window_side();
  const Bounds bytes = Bounds::at_least(1);
  static const FieldList<C> list = {
      field("clock_mhz", &C::clock_mhz, "MHz", "frontend clock", bounds::clock_mhz()),
      field("fe_pixels_per_cycle", &C::fe_pixels_per_cycle, "pixels/cycle",
            "the FE engine's input stream: pyramid pixels FD and IF each consume a cycle",
            bounds::pixels_per_cycle()),
      field("fd_stencil", &C::fd_stencil, "pixels",
            "FAST window side (Bresenham circle of radius 3: 7)",
            bounds::window_side(3).odd_only()),
      field("if_stencil", &C::if_stencil, "pixels",
            "Gaussian kernel side (the trace's IF window_size wins)", window.odd_only()),
      field("fc_patch", &C::fc_patch, "pixels",
            "rBRIEF patch side (the trace's FC window_size wins)",
            bounds::window_side(3).odd_only()),
      field("dc_stencil", &C::dc_stencil, "pixels", "Scharr kernel side", window.odd_only()),
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
            "DR block-matching window side (the trace's DR row wins)", window.odd_only()),
      field("dr_search", &C::dr_search, "offsets",
            "DR candidate offsets along the row (the trace's row wins)", count),
      field("pyramid_filter", &C::pyramid_filter, "pixels",
            "pyrDown's Gaussian side (DC builds the LK pyramid with it)", window.odd_only()),
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

void FrontendConfig::validate() const {
  check_fields(*this, "frontend", fields());
  // One unit per task, in task order, each of a kind that runs its task.
  if (units.size() != trace::kTasks.size()) {
    throw InputError(
        {}, "frontend.units",
        fmt::format("expected the {} tasks' units, got {}", trace::kTasks.size(), units.size()));
  }
  for (std::size_t i = 0; i < units.size(); ++i) {
    const FrontendUnitInstance& u = units[i];
    const trace::Task task = trace::kTasks[i];
    if (u.name != trace::to_string(task)) {
      throw InputError({}, "frontend.units." + u.name,
                       "expected a task of the graph (FD, IF, FC, MO, DR, DC or LSS)");
    }
    if (u.unit == nullptr) throw InputError({}, "frontend.units." + u.name, "no unit kind");
    if (u.unit->task() != task) {
      throw InputError({}, "frontend.units." + u.name + ".kind",
                       fmt::format("expected a kind that runs {}, got '{}' (it runs {})", u.name,
                                   u.unit->kind(), trace::to_string(u.unit->task())));
    }
    check_fields(u, "frontend.units." + u.name, FrontendUnitInstance::fields());
    require_field(bounds::unit_clock_ok(u.clock_mhz), "frontend.units." + u.name, "clock_mhz",
                  bounds::kUnitClockExpected, fmt::format("{}", u.clock_mhz));
  }
}

nlohmann::json FrontendConfig::to_json() const {
  nlohmann::json j = fields_to_json(*this, fields());
  nlohmann::json list = nlohmann::json::object();
  for (const FrontendUnitInstance& u : units) list[u.name] = u.to_json();
  j["units"] = list;
  return j;
}

FrontendConfig FrontendConfig::from_yaml(const YAML::Node& node, const std::string& where) {
  FrontendConfig config;
  YamlFields yaml(node, where, "frontend");
  yaml.refuse_moved(moved_keys());
  parse_fields(yaml, config, fields());
  const YAML::Node units = yaml.take("units");
  yaml.finish();
  if (units) {
    if (!units.IsMap()) yaml.fail("units", "expected a map of the tasks' units (FD, IF, ...)");
    for (const auto& item : units) {
      const std::string name = item.first.Scalar();
      if (std::none_of(trace::kTasks.begin(), trace::kTasks.end(),
                       [&](trace::Task t) { return name == trace::to_string(t); })) {
        yaml.fail("units." + name, "expected a task of the graph: FD, IF, FC, MO, DR, DC or LSS");
      }
    }
    parse_instances<FrontendUnit>(units, where, "frontend.units", config.units);
  }
  validate_at(yaml, [&config] { config.validate(); });
  return config;
}

std::vector<ReferenceRow> FrontendConfig::reference() {
  std::vector<ReferenceRow> rows = reference_rows("frontend", fields());
  rows.push_back(reference_row("frontend", "units", FieldKind::kText, "",
                               std::string("the seven units of Sec. V"), {}, {},
                               "the units, a map from each task (FD, IF, FC, MO, DR, DC, LSS) to "
                               "its unit (below)"));
  for (ReferenceRow& row : instance_reference<FrontendUnit, FrontendUnitInstance>(
           "frontend.units", "<task>",
           "FD: fast, IF: gaussian, FC: rbrief, MO: hamming, DR: sad_disparity, "
           "DC: scharr_pyramid, LSS: lk_solver")) {
    rows.push_back(std::move(row));
  }
  return rows;
}

}  // namespace edx::arch
