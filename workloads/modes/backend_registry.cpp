#include "workloads/modes/backend_registry.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <stdexcept>
#include <utility>

#include "workloads/backend/registration/bow/vocabulary.hpp"
#include "workloads/backend/registration/registration_backend.hpp"
#include "workloads/backend/slam/map.hpp"
#include "workloads/backend/slam/slam_backend.hpp"
#include "workloads/backend/vio/vio_backend.hpp"

namespace edx::modes {
namespace {

struct Entry {
  const char* name;
  BackendFactory factory;
};

/// The backends by name, their options at `precision`.
std::vector<Entry> entries(trace::Precision precision = trace::Precision::kFp64) {
  std::vector<Entry> list;
  list.push_back({"none", BackendFactory{}});
  list.push_back({"vio", [precision](const datasets::Dataset& d) {
                    backend::vio::VioOptions options;
                    options.precision = precision;
                    return backend::vio::make_vio_backend(d, options);
                  }});
  list.push_back({"slam", [precision](const datasets::Dataset& d) {
                    backend::slam::SlamOptions options;
                    options.precision = precision;
                    return backend::slam::make_slam_backend(d, options);
                  }});
  list.push_back({"registration", BackendFactory{}});  // needs files: registration_factory
  return list;
}

BackendFactory registration_factory(const BackendSettings& settings) {
  if (!settings.map) throw std::runtime_error("--map: the registration backend needs a map file");
  if (!settings.vocabulary) {
    throw std::runtime_error("--vocab: the registration backend needs a vocabulary file");
  }
  auto map = std::make_shared<const backend::slam::Map>(backend::slam::load_map(*settings.map));
  if (map->keyframes.empty() || map->landmarks.empty()) {
    throw std::runtime_error(
        fmt::format("{}: expected a map with keyframes and landmarks", settings.map->string()));
  }
  auto vocabulary =
      std::make_shared<const bow::Vocabulary>(bow::Vocabulary::load(*settings.vocabulary));
  backend::registration::RegistrationOptions options;
  options.precision = settings.precision;
  return [map, vocabulary, options](const datasets::Dataset& d) {
    return backend::registration::make_registration_backend(d, options, map, vocabulary);
  };
}

}  // namespace

std::vector<std::string> backend_names() {
  std::vector<std::string> names;
  for (const Entry& e : entries()) names.emplace_back(e.name);
  return names;
}

BackendFactory backend_factory(std::string_view name, const BackendSettings& settings) {
  if (name == "registration") return registration_factory(settings);
  for (Entry& e : entries(settings.precision)) {
    if (name != e.name) continue;
    if (settings.map) {
      throw std::runtime_error(
          fmt::format("--map {}: only the registration backend reads a map (got --backend {})",
                      settings.map->string(), name));
    }
    if (settings.vocabulary) {
      throw std::runtime_error(fmt::format(
          "--vocab {}: only the registration backend reads a vocabulary (got --backend {})",
          settings.vocabulary->string(), name));
    }
    return std::move(e.factory);
  }
  throw std::runtime_error(fmt::format("unknown backend '{}' (expected one of: {})", name,
                                       fmt::join(backend_names(), ", ")));
}

}  // namespace edx::modes
