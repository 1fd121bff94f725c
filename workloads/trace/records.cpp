#include "workloads/trace/records.hpp"

#include <fmt/core.h>

#include <stdexcept>
#include <string_view>
#include <utility>

namespace edx::trace {
namespace {

template <typename Enum, std::size_t N>
using NameTable = std::array<std::pair<Enum, const char*>, N>;

constexpr NameTable<Task, 7> kTaskNames{{{Task::FD, "FD"},
                                         {Task::IF, "IF"},
                                         {Task::FC, "FC"},
                                         {Task::MO, "MO"},
                                         {Task::DR, "DR"},
                                         {Task::DC, "DC"},
                                         {Task::LSS, "LSS"}}};
constexpr NameTable<Image, 3> kImageNames{
    {{Image::Left, "L"}, {Image::Right, "R"}, {Image::Stereo, "LR"}}};
constexpr NameTable<Scenario, 4> kScenarioNames{{{Scenario::IndoorUnknown, "indoor_unknown"},
                                                 {Scenario::IndoorKnown, "indoor_known"},
                                                 {Scenario::OutdoorUnknown, "outdoor_unknown"},
                                                 {Scenario::OutdoorKnown, "outdoor_known"}}};
constexpr NameTable<BackendMode, 4> kModeNames{{{BackendMode::None, "none"},
                                                {BackendMode::Registration, "registration"},
                                                {BackendMode::Vio, "vio"},
                                                {BackendMode::Slam, "slam"}}};
constexpr NameTable<Op, 9> kOpNames{{{Op::Gemm, "gemm"},
                                     {Op::Syrk, "syrk"},
                                     {Op::Potrf, "potrf"},
                                     {Op::Ldlt, "ldlt"},
                                     {Op::Trsm, "trsm"},
                                     {Op::Trsv, "trsv"},
                                     {Op::Transpose, "transpose"},
                                     {Op::Inverse, "inverse"},
                                     {Op::Qr, "qr"}}};
constexpr NameTable<Precision, 2> kPrecisionNames{
    {{Precision::kFp64, "fp64"}, {Precision::kFp32, "fp32"}}};

template <typename Enum, std::size_t N>
const char* name_of(const NameTable<Enum, N>& table, Enum value) {
  for (const auto& [entry, name] : table) {
    if (entry == value) return name;
  }
  throw std::logic_error("trace: enum value without a name");
}

template <typename Enum, std::size_t N>
Enum parse_name(const NameTable<Enum, N>& table, std::string_view kind, const std::string& text) {
  for (const auto& [entry, name] : table) {
    if (text == name) return entry;
  }
  std::string accepted;  // the names, for the error only
  for (const auto& [entry, name] : table) {
    accepted += accepted.empty() ? name : std::string("|") + name;
  }
  throw std::invalid_argument(fmt::format("unknown {} '{}' (expected {})", kind, text, accepted));
}

}  // namespace

const char* to_string(Task task) { return name_of(kTaskNames, task); }
const char* to_string(Image image) { return name_of(kImageNames, image); }
const char* to_string(Scenario scenario) { return name_of(kScenarioNames, scenario); }
const char* to_string(BackendMode mode) { return name_of(kModeNames, mode); }
const char* to_string(Op op) { return name_of(kOpNames, op); }

Task parse_task(const std::string& text) { return parse_name(kTaskNames, "task", text); }
Image parse_image(const std::string& text) { return parse_name(kImageNames, "image", text); }
Scenario parse_scenario(const std::string& text) {
  return parse_name(kScenarioNames, "scenario", text);
}
BackendMode parse_backend_mode(const std::string& text) {
  return parse_name(kModeNames, "backend mode", text);
}
Op parse_op(const std::string& text) { return parse_name(kOpNames, "op", text); }
const char* to_string(Precision precision) { return name_of(kPrecisionNames, precision); }
Precision parse_precision(const std::string& text) {
  return parse_name(kPrecisionNames, "precision", text);
}

bool computed_at_trace_precision(const std::string& kernel) {
  for (const char* name : kKernelsAtTracePrecision) {
    if (kernel == name) return true;
  }
  return false;
}

Precision trace_precision(const TraceMeta& meta) {
  const auto found = meta.find("precision");
  if (found == meta.end()) throw std::invalid_argument("meta lacks key 'precision'");
  return parse_precision(found->second);
}

}  // namespace edx::trace
