#pragma once
// The backends `edx trace --backend NAME` can run, by name, with their default options, and the
// files some of them need (the registration backend: a map and a vocabulary).
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "workloads/modes/trace_runner.hpp"

namespace edx::modes {

/// Names accepted by backend_factory: "none" first, then every backend built in.
std::vector<std::string> backend_names();

/// Inputs of the backends beyond the dataset (`edx trace --map --vocab`).
struct BackendSettings {
  std::optional<std::filesystem::path> map;         ///< map file (slam::save_map format)
  std::optional<std::filesystem::path> vocabulary;  ///< vocabulary file (edx vocab)
  /// The arithmetic of the backend's offloadable kernels (`edx trace --precision`).
  trace::Precision precision = trace::Precision::kFp64;
};

/// The factory of a named backend with default options; "none" gives an empty factory (frontend
/// only). The registration backend's map and vocabulary are loaded here, once. Throws
/// std::runtime_error with one line: an unknown name (listing the known ones), a missing
/// --map/--vocab for registration or one given to another backend, or a bad map or vocabulary
/// file (naming it).
BackendFactory backend_factory(std::string_view name, const BackendSettings& settings = {});

}  // namespace edx::modes
