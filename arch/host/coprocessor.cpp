#include "arch/host/coprocessor.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <filesystem>
#include <map>

#include "common/resources.hpp"

namespace edx::arch {

const FieldList<OffloadKeys>& OffloadKeys::fields() {
  using C = OffloadKeys;
  static const FieldList<C> list = {
      field("name", &C::name, "", "the device as reports name it"),
      field("datasheet", &C::datasheet, "", "the documents its figures come from"),
      field("reference", &C::reference, "",
            "the bundled anchor CPU (configs/host/processors/) whose row times it scales"),
      field("tasks", &C::tasks, "",
            "frontend tasks it runs (DC, DR, FD, IF, LSS, ...; the CPU runs the others)"),
      field("kernels", &C::kernels, "",
            "backend kernels it runs (kalman_gain, ...; the CPU runs the others)"),
      field("launch_us", &C::launch_us, "us", "per task or kernel it runs: the call's cost",
            Bounds::at_least(0).at_most(1e6)),
      field("launch_provenance", &C::launch_provenance, "", "where launch_us comes from"),
      field("frame_setup_ms", &C::frame_setup_ms, "ms",
            "once per frame it runs anything of (no batching across frames)",
            Bounds::at_least(0).at_most(1e4)),
      field("frame_setup_provenance", &C::frame_setup_provenance, "",
            "where frame_setup_ms comes from"),
      field("sparse_efficiency", &C::sparse_efficiency, "",
            "its sustained share of the rate ratio on the backend's small sparse matrices "
            "(1: as the datasheets' peaks say)",
            Bounds::above(0).at_most(10)),
      field("sparse_efficiency_provenance", &C::sparse_efficiency_provenance, "",
            "where sparse_efficiency comes from"),
      field("sparse_efficiency_of", &C::sparse_efficiency_of, "",
            "a bundled coprocessor whose sparse_efficiency (and provenance) this one takes "
            "(\"\": none)"),
  };
  return list;
}

namespace {

/// A row list of the keys and the part its names are of.
struct Listed {
  CostPart part;
  const std::vector<std::string>* names;
  const char* key;
};

}  // namespace

bool OffloadDevice::runs(CostPart part, std::string_view kind) const {
  const std::vector<std::string>& names = part == CostPart::kFrontendTask ? keys_.tasks
                                          : part == CostPart::kBackendKernel
                                              ? keys_.kernels
                                              : std::vector<std::string>{};
  return std::find(names.begin(), names.end(), kind) != names.end();
}

void OffloadDevice::validate_keys(const OffloadKeys& keys, std::string_view kind,
                                  const std::function<bool(ThroughputClass)>& supports) {
  const std::string section = "coprocessor";
  check_fields(keys, section, OffloadKeys::fields());
  for (const Listed& l : {Listed{CostPart::kFrontendTask, &keys.tasks, "tasks"},
                          Listed{CostPart::kBackendKernel, &keys.kernels, "kernels"}}) {
    for (const std::string& name : *l.names) {
      require_field(
          has_declared_bound(l.part, name), section, l.key,
          fmt::format("{} names edx knows (docs/MODEL.md, each kind's bound), got '{}'",
                      l.part == CostPart::kFrontendTask ? "frontend tasks" : "backend kernels",
                      name));
      const ThroughputClass c = bound_of(l.part, name);
      require_field(
          supports(c), section, l.key,
          fmt::format("rows a {} runs, got '{}', bound by {} work", kind, name, to_string(c)));
    }
  }
  // The reference must be a bundled anchor (a processor with suite times).
  try {
    bundled_description_file("configs/host/processors", "processor", keys.reference);
  } catch (const InputError& e) {
    require_field(false, section, "reference", e.expected(), keys.reference);
  }
  const std::shared_ptr<const HostProcessor> ref =
      make_host_processor("datasheet", fmt::format("{{processor: {}}}", keys.reference));
  require_field(ref->params_json().value("reference", std::string()).empty(), section, "reference",
                fmt::format("an anchor processor (one with suite times), got '{}', itself "
                            "predicted",
                            keys.reference));
}

PlatformHostTimes OffloadDevice::device_times(const std::vector<trace::FrameTrace>& frames,
                                              const trace::TraceMeta& trace_meta,
                                              const std::string& trace_name) const {
  const std::shared_ptr<const HostProcessor> ref =
      make_host_processor("datasheet", fmt::format("{{processor: {}}}", keys_.reference));
  const nlohmann::json ref_rates = ref->params_json().at("rates");
  PlatformHostTimes t = ref->host_times(frames, trace_meta, trace_name);
  // t_dev = t_ref × rate_ref(class) / (rate_dev(class) × e(part)), rows it runs only.
  std::map<std::pair<CostPart, std::string>, double> factors;
  const auto factor = [&](CostPart part, const std::string& kind) {
    const auto key = std::make_pair(part, kind);
    auto it = factors.find(key);
    if (it == factors.end()) {
      double f = 1;
      if (runs(part, kind)) {
        const ThroughputClass c = bound_of(part, kind);
        const double e = part == CostPart::kBackendKernel ? keys_.sparse_efficiency : 1.0;
        f = ref_rates.at(to_string(c)).get<double>() / (rate(c) * e);
      }
      it = factors.emplace(key, f).first;
    }
    return it->second;
  };
  for (std::size_t f = 0; f < frames.size(); ++f) {
    for (std::size_t i = 0; i < frames[f].tasks.size(); ++i) {
      t.task_ms[f][i] *= factor(CostPart::kFrontendTask, trace::to_string(frames[f].tasks[i].task));
    }
    for (std::size_t k = 0; k < frames[f].kernels.size(); ++k) {
      t.kernel_ms[f][k] *= factor(CostPart::kBackendKernel, frames[f].kernels[k].kernel);
    }
  }
  t.mapping.append_basis(fmt::format("; on {}: its rows x rate({}) / rate(device) per bound",
                                     keys_.name, keys_.reference));
  return t;
}

std::string OffloadDevice::bundled_file(const std::string& name) {
  return bundled_description_file("configs/host/coprocessors", "coprocessor", name);
}

YamlFields bundled_coprocessor_yaml(const std::string& name, const std::string& kind) {
  const std::string where = OffloadDevice::bundled_file(name);
  YamlFields yaml(load_yaml_map(read_input_file(where, "coprocessor description"), where, ""),
                  where, "");
  const YAML::Node node = yaml.take("kind");
  const std::string got = node && node.IsScalar() ? node.as<std::string>() : std::string();
  if (got != kind) {
    yaml.fail("kind", fmt::format("expected '{}' (the kind that reads it), got '{}'", kind, got));
  }
  return yaml;
}

void OffloadDevice::share_sparse_efficiency(const YamlFields& yaml, OffloadKeys& keys) {
  if (keys.sparse_efficiency_of.empty()) return;
  try {
    bundled_file(keys.sparse_efficiency_of);
  } catch (const InputError& e) {
    yaml.fail(e.with_key("sparse_efficiency_of"));
  }
  // The other description's own keys (any kind: the efficiency is of the sparse work).
  const std::string where = bundled_file(keys.sparse_efficiency_of);
  const YAML::Node other =
      load_yaml_map(read_input_file(where, "coprocessor description"), where, "");
  const YAML::Node shared = other["sparse_efficiency_of"];
  if (shared && shared.IsScalar() && !shared.as<std::string>().empty()) {
    yaml.fail("sparse_efficiency_of",
              fmt::format("expected a coprocessor that states its own sparse_efficiency, got "
                          "'{}', which shares another's",
                          keys.sparse_efficiency_of));
  }
  if (!other["sparse_efficiency"]) {
    yaml.fail("sparse_efficiency_of",
              fmt::format("expected a coprocessor that states a sparse_efficiency, got '{}'",
                          keys.sparse_efficiency_of));
  }
  keys.sparse_efficiency = other["sparse_efficiency"].as<double>();
  keys.sparse_efficiency_provenance =
      fmt::format("{}'s: {}", keys.sparse_efficiency_of,
                  other["sparse_efficiency_provenance"]
                      ? other["sparse_efficiency_provenance"].as<std::string>()
                      : std::string("(no provenance stated)"));
}

std::shared_ptr<const Coprocessor> make_coprocessor(std::string_view kind,
                                                    const std::string& params) {
  YamlFields fields(YAML::Load(params), "code", "coprocessor");
  return ComponentRegistry<Coprocessor>::instance().at(kind).parse(fields);
}

}  // namespace edx::arch
