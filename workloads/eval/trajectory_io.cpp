#include "workloads/eval/trajectory_io.hpp"

#include <fmt/core.h>

#include <charconv>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <utility>
#include <variant>
#include <vector>

namespace edx::eval {
namespace {

/// Throws "source:line: message".
[[noreturn]] void fail_at(const std::string& source, std::size_t line, const std::string& message) {
  throw std::runtime_error(fmt::format("{}:{}: {}", source, line, message));
}

std::string_view trim(std::string_view text) {
  const auto first = text.find_first_not_of(" \t\r\n");
  if (first == std::string_view::npos) return {};
  const auto last = text.find_last_not_of(" \t\r\n");
  return text.substr(first, last - first + 1);
}

/// Whitespace-separated tokens (KITTI, TUM).
std::vector<std::string_view> split_whitespace(std::string_view text) {
  std::vector<std::string_view> tokens;
  std::size_t pos = 0;
  while (true) {
    pos = text.find_first_not_of(" \t\r", pos);
    if (pos == std::string_view::npos) break;
    const auto end = text.find_first_of(" \t\r", pos);
    tokens.push_back(text.substr(pos, end == std::string_view::npos ? end : end - pos));
    if (end == std::string_view::npos) break;
    pos = end;
  }
  return tokens;
}

/// Comma-separated fields, each trimmed (EuRoC).
std::vector<std::string_view> split_commas(std::string_view text) {
  std::vector<std::string_view> fields;
  std::size_t pos = 0;
  while (true) {
    const auto comma = text.find(',', pos);
    fields.push_back(trim(text.substr(pos, comma == std::string_view::npos ? comma : comma - pos)));
    if (comma == std::string_view::npos) break;
    pos = comma + 1;
  }
  return fields;
}

/// What poses are sorted by, compared exactly: frame index or EuRoC nanoseconds (integers), TUM
/// seconds (double as written).
struct SortKey {
  std::variant<std::int64_t, double> value;
  std::string text;  ///< as shown in messages, e.g. "timestamp 1.5 s"
};

/// The largest position coordinate read (m). Positions are differenced, squared and summed in
/// double: at 10^9 m a coordinate still resolves 2·10^-7 m, and sums of squares stay far from
/// overflow (beyond about 10^154 m they are inf: an ATE of inf, or of a plausible-looking 84 m
/// from what rounding leaves). GPS's Earth-centred coordinates are below 7·10^6 m.
constexpr double kMaxCoordinateM = 1e9;

/// One line of a file being parsed: its tokens and where it came from.
struct Row {
  const std::string& source;
  std::size_t line;
  std::vector<std::string_view> tokens;

  /// The finite number in token `column` (0-based; messages count from 1).
  double number(std::size_t column) const {
    std::string_view token = tokens[column];
    if (token.size() > 1 && token.front() == '+' && token[1] != '-') token.remove_prefix(1);
    double value = 0.0;
    const auto [end, error] = std::from_chars(token.data(), token.data() + token.size(), value);
    if (error == std::errc::result_out_of_range) {
      fail_at(source, line,
              fmt::format("'{}' is out of the range of a double (column {})", tokens[column],
                          column + 1));
    }
    if (error != std::errc() || end != token.data() + token.size()) {
      fail_at(source, line,
              fmt::format("'{}' is not a number (column {})", tokens[column], column + 1));
    }
    if (!std::isfinite(value)) {
      fail_at(source, line,
              fmt::format("non-finite value '{}' (column {})", tokens[column], column + 1));
    }
    return value;
  }

  /// A position coordinate in token `column`: a number of at most kMaxCoordinateM in magnitude.
  double coordinate(std::size_t column) const {
    const double value = number(column);
    if (!(std::abs(value) <= kMaxCoordinateM)) {
      fail_at(source, line,
              fmt::format("position {} m is beyond the {:g} m edx evaluates (column {})",
                          tokens[column], kMaxCoordinateM, column + 1));
    }
    return value;
  }

  /// The non-negative integer in token `column`, written as an integer or an integral decimal.
  std::int64_t index(std::size_t column, std::string_view what) const {
    const double value = number(column);
    if (value < 0.0 || value != std::floor(value) || value > 9.0e15) {
      fail_at(source, line,
              fmt::format("{} '{}' is not a non-negative integer", what, tokens[column]));
    }
    return static_cast<std::int64_t>(value);
  }
};

/// Checks that R is a rotation: max|R^T R - I| <= tolerance and det R > 0.
void check_rotation(const Row& row, const Eigen::Matrix3d& rotation, double tolerance) {
  const double deviation =
      (rotation.transpose() * rotation - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (!(deviation <= tolerance)) {
    fail_at(row.source, row.line,
            fmt::format("rotation is not orthonormal (max |R^T R - I| = {:.3g}, tolerance {:.3g})",
                        deviation, tolerance));
  }
  if (rotation.determinant() <= 0.0) {
    fail_at(row.source, row.line, "rotation has a negative determinant (a reflection)");
  }
}

/// The rotation of a quaternion whose norm is 1 within tolerance (normalised before use).
Eigen::Matrix3d quaternion_rotation(const Row& row, double w, double x, double y, double z,
                                    double tolerance) {
  Eigen::Quaterniond q(w, x, y, z);
  const double norm = q.norm();
  if (!(std::abs(norm - 1.0) <= tolerance)) {
    fail_at(row.source, row.line,
            fmt::format("quaternion norm {:.6g} is not 1 (tolerance {:.3g})", norm, tolerance));
  }
  q.normalize();
  return q.toRotationMatrix();
}

Pose make_pose(const Eigen::Matrix3d& rotation, const Eigen::Vector3d& position) {
  Pose pose = Pose::Identity();
  pose.linear() = rotation;
  pose.translation() = position;
  return pose;
}

/// Parses one KITTI row: 12 numbers [R|t] row-major, or a frame index and those 12.
StampedPose parse_kitti_row(const Row& row, std::optional<std::size_t>& columns_of_file,
                            std::size_t ordinal, double tolerance) {
  const std::size_t count = row.tokens.size();
  if (count != 12 && count != 13) {
    fail_at(row.source, row.line, fmt::format("expected 12 or 13 numbers, got {}", count));
  }
  if (!columns_of_file) {
    columns_of_file = count;
  } else if (count != *columns_of_file) {
    fail_at(row.source, row.line,
            fmt::format("expected {} numbers as on the first pose line, got {}", *columns_of_file,
                        count));
  }
  const std::size_t offset = count == 13 ? 1 : 0;
  StampedPose stamped;
  stamped.line = row.line;
  stamped.frame_index =
      offset == 1 ? row.index(0, "frame index") : static_cast<std::int64_t>(ordinal);
  stamped.time_s = static_cast<double>(stamped.frame_index);
  Eigen::Matrix3d rotation;
  Eigen::Vector3d position;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) rotation(r, c) = row.number(offset + 4 * r + c);
    position(r) = row.coordinate(offset + 4 * r + 3);
  }
  check_rotation(row, rotation, tolerance);
  stamped.pose = make_pose(rotation, position);
  return stamped;
}

/// Parses one TUM row: t x y z qx qy qz qw.
StampedPose parse_tum_row(const Row& row, std::size_t ordinal, double tolerance) {
  if (row.tokens.size() != 8) {
    fail_at(row.source, row.line,
            fmt::format("expected 8 numbers (t x y z qx qy qz qw), got {}", row.tokens.size()));
  }
  double v[8];
  for (std::size_t i = 0; i < 8; ++i) v[i] = i >= 1 && i <= 3 ? row.coordinate(i) : row.number(i);
  StampedPose stamped;
  stamped.line = row.line;
  stamped.frame_index = static_cast<std::int64_t>(ordinal);
  stamped.time_s = v[0];
  stamped.pose = make_pose(quaternion_rotation(row, v[7], v[4], v[5], v[6], tolerance),
                           Eigen::Vector3d(v[1], v[2], v[3]));
  return stamped;
}

/// Parses one EuRoC row: timestamp_ns, px, py, pz, qw, qx, qy, qz, ... (extra columns ignored).
StampedPose parse_euroc_row(const Row& row, std::size_t ordinal, SortKey& key, double tolerance) {
  if (row.tokens.size() < 8) {
    fail_at(row.source, row.line,
            fmt::format("expected at least 8 comma-separated values (timestamp_ns, px, py, pz, qw, "
                        "qx, qy, qz), got {}",
                        row.tokens.size()));
  }
  const std::string_view stamp = row.tokens[0];
  std::int64_t stamp_ns = 0;
  const auto [end, error] = std::from_chars(stamp.data(), stamp.data() + stamp.size(), stamp_ns);
  if (error != std::errc() || end != stamp.data() + stamp.size() || stamp_ns < 0) {
    fail_at(row.source, row.line,
            fmt::format("timestamp '{}' is not a non-negative integer in ns (column 1)", stamp));
  }
  double v[8];
  for (std::size_t i = 1; i < 8; ++i) v[i] = i <= 3 ? row.coordinate(i) : row.number(i);
  StampedPose stamped;
  stamped.line = row.line;
  stamped.frame_index = static_cast<std::int64_t>(ordinal);
  stamped.time_s = static_cast<double>(stamp_ns) * 1e-9;
  key = {stamp_ns, fmt::format("timestamp {} ns", stamp_ns)};
  stamped.pose = make_pose(quaternion_rotation(row, v[4], v[5], v[6], v[7], tolerance),
                           Eigen::Vector3d(v[1], v[2], v[3]));
  return stamped;
}

}  // namespace

TrajectoryFormat parse_trajectory_format(std::string_view name) {
  if (name == "kitti") return TrajectoryFormat::kKitti;
  if (name == "tum") return TrajectoryFormat::kTum;
  if (name == "euroc") return TrajectoryFormat::kEuroc;
  throw std::runtime_error(
      fmt::format("unknown trajectory format '{}' (expected kitti, tum or euroc)", name));
}

std::string_view trajectory_format_name(TrajectoryFormat format) {
  switch (format) {
    case TrajectoryFormat::kKitti:
      return "kitti";
    case TrajectoryFormat::kTum:
      return "tum";
    case TrajectoryFormat::kEuroc:
      return "euroc";
  }
  return "unknown";
}

Trajectory parse_trajectory(std::istream& in, const std::string& source, TrajectoryFormat format,
                            const ReadOptions& options) {
  Trajectory trajectory;
  trajectory.source = source;
  trajectory.stamp_kind =
      format == TrajectoryFormat::kKitti ? StampKind::kFrameIndex : StampKind::kSeconds;

  std::optional<std::size_t> kitti_columns;
  std::optional<SortKey> previous_key;
  std::size_t previous_line = 0;

  std::string text;
  for (std::size_t line = 1; std::getline(in, text); ++line) {
    const std::string_view content = trim(text);
    if (content.empty() || content.front() == '#') continue;  // blank, comment or header
    const Row row{
        source, line,
        format == TrajectoryFormat::kEuroc ? split_commas(content) : split_whitespace(content)};
    const std::size_t ordinal = trajectory.poses.size();
    SortKey key;
    StampedPose stamped;
    switch (format) {
      case TrajectoryFormat::kKitti:
        stamped = parse_kitti_row(row, kitti_columns, ordinal, options.rotation_tolerance);
        key = {stamped.frame_index, fmt::format("frame index {}", stamped.frame_index)};
        break;
      case TrajectoryFormat::kTum:
        stamped = parse_tum_row(row, ordinal, options.rotation_tolerance);
        key = {stamped.time_s, fmt::format("timestamp {} s", row.tokens[0])};
        break;
      case TrajectoryFormat::kEuroc:
        stamped = parse_euroc_row(row, ordinal, key, options.rotation_tolerance);
        break;
    }
    if (previous_key && key.value == previous_key->value) {
      // A frame index names one frame: a repeat is an error. Real ground truth repeats
      // timestamps (e.g. the TUM RGB-D files): keep the first pose of a stamp, drop the rest,
      // and count them (docs/EVAL.md). Going back in time stays an error.
      if (format == TrajectoryFormat::kKitti) {
        fail_at(source, line,
                fmt::format("duplicate {} (also on line {})", key.text, previous_line));
      }
      if (trajectory.repeated_stamps_dropped++ == 0) trajectory.first_repeated_line = line;
      continue;
    }
    if (previous_key && key.value < previous_key->value) {
      fail_at(source, line,
              fmt::format("{} comes after {} on line {}: poses must be sorted", key.text,
                          previous_key->text, previous_line));
    }
    previous_key = std::move(key);
    previous_line = line;
    trajectory.poses.push_back(stamped);
  }
  if (in.bad()) throw std::runtime_error(fmt::format("{}: read error", source));
  if (trajectory.poses.empty()) {
    throw std::runtime_error(fmt::format("{}: no poses found (expected {} format)", source,
                                         trajectory_format_name(format)));
  }
  return trajectory;
}

Trajectory read_trajectory(const std::filesystem::path& path, TrajectoryFormat format,
                           const ReadOptions& options) {
  if (std::filesystem::is_directory(path)) {
    throw std::runtime_error(
        fmt::format("{}: is a directory (expected a trajectory file)", path.string()));
  }
  std::ifstream in(path);
  if (!in) {
    throw std::runtime_error(fmt::format("{}: cannot open trajectory file", path.string()));
  }
  return parse_trajectory(in, path.string(), format, options);
}

}  // namespace edx::eval
