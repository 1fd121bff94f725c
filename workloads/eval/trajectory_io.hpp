#pragma once
// Readers of trajectory files in the KITTI, TUM and EuRoC formats. Every defect of a file (short
// row, non-numeric or non-finite token, unsorted or duplicate stamp, rotation that is not
// orthonormal) is reported as a std::runtime_error "FILE:LINE: what was expected".
#include <filesystem>
#include <istream>
#include <string>
#include <string_view>

#include "workloads/eval/trajectory.hpp"

namespace edx::eval {

enum class TrajectoryFormat {
  kKitti,  ///< "r11 r12 r13 tx r21 ... tz" (row-major 3x4 [R|t]), optionally led by a frame index
  kTum,    ///< "t x y z qx qy qz qw", t in seconds
  kEuroc,  ///< CSV "timestamp_ns, px, py, pz, qw, qx, qy, qz[, ...]", '#' header
};

struct ReadOptions {
  /// Largest accepted max|R^T R - I| (KITTI) or | |q| - 1 | (TUM, EuRoC).
  double rotation_tolerance = 1e-3;
};

/// "kitti", "tum" or "euroc"; throws std::runtime_error on anything else.
TrajectoryFormat parse_trajectory_format(std::string_view name);
std::string_view trajectory_format_name(TrajectoryFormat format);

/// Reads a trajectory file; error messages name `path` as given.
Trajectory read_trajectory(const std::filesystem::path& path, TrajectoryFormat format,
                           const ReadOptions& options = {});

/// Parses a trajectory from a stream; `source` names it in error messages.
Trajectory parse_trajectory(std::istream& in, const std::string& source, TrajectoryFormat format,
                            const ReadOptions& options = {});

}  // namespace edx::eval
