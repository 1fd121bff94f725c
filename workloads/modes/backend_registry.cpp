#include "workloads/modes/backend_registry.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <stdexcept>
#include <utility>

#include "workloads/backend/slam/slam_backend.hpp"
#include "workloads/backend/vio/vio_backend.hpp"

namespace edx::modes {
namespace {

struct Entry {
  const char* name;
  BackendFactory factory;
};

std::vector<Entry> entries() {
  std::vector<Entry> list;
  list.push_back({"none", BackendFactory{}});
  list.push_back({"vio", [](const datasets::Dataset& d) {
                    return backend::vio::make_vio_backend(d, backend::vio::VioOptions{});
                  }});
  list.push_back({"slam", [](const datasets::Dataset& d) {
                    return backend::slam::make_slam_backend(d, backend::slam::SlamOptions{});
                  }});
  return list;
}

}  // namespace

std::vector<std::string> backend_names() {
  std::vector<std::string> names;
  for (const Entry& e : entries()) names.emplace_back(e.name);
  return names;
}

BackendFactory backend_factory(std::string_view name) {
  for (Entry& e : entries()) {
    if (name == e.name) return std::move(e.factory);
  }
  throw std::runtime_error(fmt::format("unknown backend '{}' (expected one of: {})", name,
                                       fmt::join(backend_names(), ", ")));
}

}  // namespace edx::modes
