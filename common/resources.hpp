#pragma once
// edx's own files read at run time (reports/paper_targets.yaml; configs/ and sweeps/ for users):
// found beside the running binary once installed, else in the source tree it was built from.
#include <filesystem>
#include <string>

namespace edx::common {

/// The folder holding edx's files, laid out as the source tree (configs/, sweeps/, reports/).
struct DataRoot {
  std::filesystem::path path;  ///< empty when no candidate exists
  std::string how;             ///< how it was chosen, e.g. "installed beside /opt/edx/bin/edx"
};

/// In order: $EDX_DATA_DIR when set (taken as is); `<bindir>/../share/edx` of the running
/// binary (/proc/self/exe, as `cmake --install` lays it out) when that folder exists; the source
/// tree of the build when it exists. An installed edx therefore never reads the source tree.
DataRoot data_root();

/// The existing file or folder `relative` (e.g. "reports/paper_targets.yaml") under data_root().
/// Throws std::runtime_error naming what was looked for and where.
std::filesystem::path find_resource(const std::filesystem::path& relative);

}  // namespace edx::common
