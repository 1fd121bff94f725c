// A CPU described by its datasheet (docs/MODEL.md, "Host CPU: processors from their
// datasheets"; issue 41): cores, clock, issue width, SIMD width and pipes, flops a cycle per
// precision, caches, DRAM bandwidth and package power. One of two roles:
//
//   anchor     it states its own times on the reference suite (calibrated against paper
//              figures: the Kaby Lake); its host times are the suite_scaled kind's
//   predicted  it names an anchor (`reference:`); each row's time is the anchor's times its
//              bound's rate ratio (arch/host/throughput.hpp):
//                t(row) = t_ref(row) × rate_ref(class) / (rate(class) × efficiency)
//
// `processor: NAME` starts from the bundled description configs/host/processors/NAME.yaml (its
// keys the defaults, the platform's keys over them), as a link's `preset:` does.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <map>
#include <memory>
#include <mutex>
#include <utility>

#include "arch/host/host_processor.hpp"
#include "arch/host/throughput.hpp"
#include "common/input_error.hpp"
#include "common/resources.hpp"
#include "common/yaml_fields.hpp"

namespace edx::arch {
namespace {

class Datasheet final : public HostProcessor {
 public:
  struct Params {
    std::string processor;  ///< the bundled description started from ("" none)
    std::string name = "Intel Kaby Lake, 4 cores, 1.6 GHz (paper Sec. VII-A)";
    std::string datasheet = "see docs/MODEL.md";  ///< where the figures below come from
    int cores = 4;
    ProcessorDatasheet sheet;
    /// An anchor's times on the reference suite (0: predicted), and `times`.
    SuiteTimeKeys suite;
    // Predicted: the anchor it is predicted from, and its efficiency relative to it.
    std::string reference_name;  ///< `reference:` ("" an anchor)
    double efficiency = 1.0;
    std::string efficiency_provenance = "1: the datasheet peaks' ratio as it is";
    /// A bundled processor whose efficiency this one shares (same ISA and code; "" none).
    std::string efficiency_of;
    HostPower power{15.0, 2.0};

    bool anchor() const { return reference_name.empty(); }

    static const FieldList<Params>& fields() {
      using C = Params;
      static const FieldList<C> list = joined<C>({
          {
              field("name", &C::name, "", "the processor as reports name it"),
              field("datasheet", &C::datasheet, "", "the documents its figures come from"),
              field("cores", &C::cores, "", "cores the DES gives the host's threads",
                    Bounds::at_least(1).at_most(256)),
          },
          nested_fields<C>("", &C::sheet, ProcessorDatasheet::fields()),
          nested_fields<C>("", &C::suite, SuiteTimeKeys::fields()),
          {
              field("reference", &C::reference_name, "",
                    "the bundled anchor processor (configs/host/processors/) this one is "
                    "predicted from by its bounds' rate ratios (\"\": it is an anchor)"),
              field("efficiency", &C::efficiency, "",
                    "sustained share of the rate ratio on the pipeline's code (1: as the "
                    "datasheets' peaks say)",
                    Bounds::above(0).at_most(10)),
              field("efficiency_provenance", &C::efficiency_provenance, "",
                    "where efficiency comes from"),
              field("efficiency_of", &C::efficiency_of, "",
                    "a bundled predicted processor whose efficiency (and its provenance) this "
                    "one takes: the same instruction set running the same code (\"\": none)"),
          },
          nested_fields<C>("", &C::power, HostPower::fields()),
      });
      return list;
    }

    void validate() const {
      check_fields(*this, "host", fields());
      if (anchor()) {
        require_field(suite.frontend_suite_ms > 0 && suite.backend_suite_ms > 0, "host",
                      "frontend_suite_ms",
                      "both suite times of an anchor processor, or a `reference` to predict "
                      "it from");
        require_field(efficiency == 1.0, "host", "efficiency",
                      "1 on an anchor (its suite times are its speed)");
      } else {
        require_field(suite.frontend_suite_ms == 0 && suite.backend_suite_ms == 0, "host",
                      "frontend_suite_ms",
                      "no suite times on a processor predicted from a `reference`");
      }
      power.validate();
    }

    /// The file of bundled description `name`, configs/host/processors/NAME.yaml; throws
    /// InputError "expected a bundled processor (the names), got ..." when there is none.
    static std::string bundled_file(const std::string& name) {
      return bundled_description_file("configs/host/processors", "processor", name);
    }

    /// The bundled description `name` read as a host map (errors name its file and line).
    /// `share`: take an `efficiency_of`'s efficiency (else leave it named, unresolved).
    /// Bundled descriptions are read-only resources: each (file, share) is parsed once per
    /// process and copied from then on (a sweep parses its platform once per point). A file
    /// that fails to parse is not kept: it fails again, with the same error, every time.
    static Params bundled(const std::string& name, bool share = true) {
      const std::string where = bundled_file(name);
      static std::mutex mutex;
      static std::map<std::pair<std::string, bool>, Params> parsed;
      {
        const std::lock_guard<std::mutex> lock(mutex);
        if (auto it = parsed.find({where, share}); it != parsed.end()) return it->second;
      }
      Params p = parse_bundled(where, name, share);
      const std::lock_guard<std::mutex> lock(mutex);
      return parsed.try_emplace({where, share}, std::move(p)).first->second;
    }

    static Params parse_bundled(const std::string& where, const std::string& name, bool share) {
      YamlFields yaml(load_yaml_map(read_input_file(where, "processor description"), where, ""),
                      where, "");
      Params p;
      parse_fields(yaml, p, fields());
      yaml.finish();
      if (share) share_efficiency(yaml, p);
      p.processor = name;
      validate_at(yaml, [&p] { p.validate(); });
      return p;
    }

    /// `efficiency_of`'s efficiency and provenance into `p` (errors at `yaml`'s key).
    static void share_efficiency(const YamlFields& yaml, Params& p) {
      if (p.efficiency_of.empty()) return;
      try {
        bundled_file(p.efficiency_of);
      } catch (const InputError& e) {
        yaml.fail(e.with_key("efficiency_of"));
      }
      const Params other = bundled(p.efficiency_of, /*share=*/false);
      if (!other.efficiency_of.empty()) {
        yaml.fail("efficiency_of", fmt::format("expected a processor that states its own "
                                               "efficiency, got '{}', which shares another's",
                                               p.efficiency_of));
      }
      p.efficiency = other.efficiency;
      p.efficiency_provenance =
          fmt::format("{}'s: {}", other.processor, other.efficiency_provenance);
    }

    /// `processor:` first (its keys the defaults), then the keys here.
    static Params parse(YamlFields& yaml) {
      Params p;
      if (const YAML::Node processor = yaml.take("processor")) {
        const FieldValue name =
            read_field_value(yaml, "processor", processor, FieldKind::kText, {}, {});
        try {
          bundled_file(std::get<std::string>(name));
        } catch (const InputError& e) {
          yaml.fail(e.with_key("processor"));
        }
        p = bundled(std::get<std::string>(name));
      }
      // Keys here override the description's; an efficiency given here replaces a shared one.
      const bool own_efficiency_of = static_cast<bool>(yaml.take("efficiency_of"));
      if (yaml.take("efficiency") && !own_efficiency_of) {
        p.efficiency_of.clear();
        p.efficiency_provenance = "set in the platform file";  // unless it says more
      }
      parse_fields(yaml, p, fields());
      if (own_efficiency_of) share_efficiency(yaml, p);
      if (!p.anchor()) {  // the reference must exist and be an anchor
        try {
          bundled_file(p.reference_name);
        } catch (const InputError& e) {
          yaml.fail(e.with_key("reference"));
        }
        if (!bundled(p.reference_name).anchor()) {
          yaml.fail("reference", fmt::format("expected an anchor processor (one with suite "
                                             "times), got '{}', itself predicted",
                                             p.reference_name));
        }
      }
      return p;
    }

    static std::vector<ReferenceRow> reference(const std::string& section,
                                               const std::string& title) {
      std::vector<ReferenceRow> rows = {reference_row(
          section, "processor", FieldKind::kText, "", std::string(), {}, {},
          "start from a bundled description, configs/host/processors/NAME.yaml (the keys below "
          "override its values)")};
      rows.back().group = title;
      for (ReferenceRow& row : reference_rows(section, fields(), Params{}, title)) {
        rows.push_back(std::move(row));
      }
      return rows;
    }
  };

  explicit Datasheet(const Params& params) : params_(params) {
    if (!params_.anchor())
      reference_ = std::make_unique<Params>(Params::bundled(params_.reference_name));
  }

  std::string_view kind() const override { return "datasheet"; }
  nlohmann::json params_json() const override {
    nlohmann::json j = params_to_json(params_);
    j["processor"] = params_.processor;
    j["rates"] = params_.sheet.rates_json();
    return j;
  }
  std::string display_name() const override { return params_.name; }
  int cores() const override { return params_.cores; }
  HostPower power() const override { return params_.power; }

  PlatformHostTimes host_times(const std::vector<trace::FrameTrace>& frames,
                               const trace::TraceMeta& trace_meta, const std::string& trace_name,
                               const HostCostModel* costs) const override {
    const Params& anchor = reference_ ? *reference_ : params_;
    const SuiteTimes suite = anchor.suite.suite_times(anchor.name);
    if (!reference_) {
      return PlatformHostTimes::suite_scaled(suite, params_.suite.times, frames, trace_meta,
                                             trace_name, costs);
    }
    // t(row) = t_ref(row) × rate_ref(class) / (rate(class) × efficiency).
    const RowFactor factor = [this](CostPart part, std::string_view kind) {
      const ThroughputClass c = bound_of(part, kind);
      return reference_->sheet.rate(c) / (params_.sheet.rate(c) * params_.efficiency);
    };
    PlatformHostTimes t = PlatformHostTimes::suite_scaled(suite, params_.suite.times, frames,
                                                          trace_meta, trace_name, costs, factor);
    t.mapping.append_basis(fmt::format(
        "; on {}: each row x rate({}) / rate(this) per its bound, efficiency {:.4g} ({})",
        params_.name, reference_->processor, params_.efficiency, params_.efficiency_provenance));
    return t;
  }

 private:
  Params params_;
  std::unique_ptr<const Params> reference_;  ///< the anchor a predicted processor scales
};

}  // namespace

EDX_REGISTER_COMPONENT(HostProcessor, Datasheet, "datasheet",
                       "a CPU by its datasheet: an anchor with calibrated suite times, or a "
                       "processor predicted from one per bound (docs/MODEL.md, Host CPU)");

}  // namespace edx::arch
