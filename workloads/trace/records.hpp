#pragma once
// Plain records of a localization trace (docs/TRACE.md): what the pipeline ran per frame, its
// host timings and the work it did in units a hardware model can use.
#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace edx::trace {

/// Frontend tasks of the paper's Sec. V-B.
enum class Task { FD, IF, FC, MO, DR, DC, LSS };
/// Every task, in declaration order (the order of their units and reports).
inline constexpr std::array<Task, 7> kTasks = {Task::FD, Task::IF, Task::FC, Task::MO,
                                               Task::DR, Task::DC, Task::LSS};
/// Which image a task ran on; MO and DR work on the stereo pair.
enum class Image { Left, Right, Stereo };
/// Operating scenarios of the paper's Sec. III.
enum class Scenario { IndoorUnknown, IndoorKnown, OutdoorUnknown, OutdoorKnown };
/// Backend mode that ran on a frame; None for frontend-only traces.
enum class BackendMode { None, Registration, Vio, Slam };
/// The arithmetic of the offloadable backend kernels (docs/TRACE.md, meta `precision`): IEEE
/// double or single. The rest of the pipeline computes in double either way.
enum class Precision { kFp64, kFp32 };
/// Matrix primitives inside the backend kernels (paper Table I, and the Householder QR of the
/// MSCKF's null-space projection).
enum class Op { Gemm, Syrk, Potrf, Ldlt, Trsm, Trsv, Transpose, Inverse, Qr };
/// Every op, in declaration order.
inline constexpr std::array<Op, 9> kOps = {Op::Gemm, Op::Syrk,      Op::Potrf,   Op::Ldlt, Op::Trsm,
                                           Op::Trsv, Op::Transpose, Op::Inverse, Op::Qr};

/// Structure flags of an op, OR-ed into OpRecord::flags.
namespace op_flags {
inline constexpr std::uint32_t kSymmetric = 1u << 0;      ///< result or operand is symmetric
inline constexpr std::uint32_t kDiagonalBlock = 1u << 1;  ///< leading block is diagonal
inline constexpr std::uint32_t kBlock6x6 = 1u << 2;       ///< trailing 6x6 pose block
inline constexpr std::uint32_t kLower = 1u << 3;          ///< lower-triangular operand
inline constexpr std::uint32_t kUpper = 1u << 4;          ///< upper-triangular operand
inline constexpr std::uint32_t kTransposeA = 1u << 5;
inline constexpr std::uint32_t kTransposeB = 1u << 6;
inline constexpr std::uint32_t kDiagonal = 1u << 7;  ///< the whole matrix is diagonal
inline constexpr std::uint32_t kAll = (1u << 8) - 1;
}  // namespace op_flags

/// A pose as translation and unit quaternion: tx, ty, tz, qw, qx, qy, qz (T_world_body).
using PoseArray = std::array<double, 7>;

/// Work done at one pyramid level by a task (pixels visited, LK iterations, ...).
struct LevelWork {
  int level = 0;
  int width = 0;
  int height = 0;
  std::int64_t pixels = 0;
  std::int64_t points = 0;      ///< points tracked at this level (LSS)
  std::int64_t iterations = 0;  ///< LK iterations summed over points at this level (LSS)
  bool operator==(const LevelWork&) const = default;
};

/// One frontend task execution. Counts that do not apply to a task stay 0.
struct TaskRecord {
  Task task = Task::FD;
  Image image = Image::Left;
  std::int64_t host_ns = 0;          ///< measured on the trace host, steady clock
  std::int64_t pixels = 0;           ///< pixels processed, all levels
  std::int64_t levels = 0;           ///< pyramid levels
  std::int64_t candidates = 0;       ///< FAST candidates before non-maximum suppression
  std::int64_t keypoints = 0;        ///< keypoints kept / handled
  std::int64_t descriptors = 0;      ///< descriptors computed
  std::int64_t comparisons = 0;      ///< Hamming-distance comparisons (MO)
  std::int64_t windows = 0;          ///< block-matching windows evaluated (DR)
  std::int64_t window_size = 0;      ///< window side in pixels (DR: 11, IF: kernel size)
  std::int64_t search_range = 0;     ///< candidate offsets per window (DR: 11 for +-5 px)
  std::int64_t points = 0;           ///< tracked points (DC, LSS)
  std::int64_t iterations = 0;       ///< iterations summed over points (LSS)
  std::vector<LevelWork> per_level;  ///< optional per-level breakdown
  bool operator==(const TaskRecord&) const = default;
};

/// One matrix primitive inside a kernel. For gemm C(m x n) = A(m x k) B(k x n); for syrk
/// C(m x m) = A(m x k) A^T; potrf/ldlt/inverse on m x m; trsm solves m x m against m x n;
/// trsv the same with n = 1; transpose of m x n; qr the Householder factorization of an m x n
/// matrix (m >= n: n reflections, R and the reflectors in place). `batch` independent instances
/// of the same shape run one after another (a kernel's per-feature or per-observation products:
/// one record, not thousands); host_ns is that of all of them.
struct OpRecord {
  Op op = Op::Gemm;
  std::int64_t m = 0, n = 0, k = 0;
  std::uint32_t flags = 0;
  std::int64_t host_ns = 0;
  std::int64_t batch = 1;
  bool operator==(const OpRecord&) const = default;
};

/// One backend kernel invocation, in execution order. The meaning of m, n, k per kernel is
/// listed in docs/TRACE.md (e.g. projection: m = map points).
struct KernelRecord {
  std::string kernel;  ///< e.g. "projection", "kalman_gain", "marginalization"
  std::int64_t host_ns = 0;
  bool accelerable = false;  ///< one of the kernels the backend accelerator can run
  std::int64_t m = 0, n = 0, k = 0;
  std::string detail_json = "{}";  ///< further sizes as a JSON object
  std::vector<OpRecord> ops;
  bool operator==(const KernelRecord&) const = default;
};

/// Per-frame summary.
struct FrameRecord {
  std::int64_t frame_id = 0;      ///< 0, 1, 2, ... in trace order
  std::int64_t timestamp_ns = 0;  ///< sensor time stamp, strictly increasing within a sequence
  std::string sequence;           ///< source sequence, e.g. "euroc:V1_01" or "synthetic:outdoor"
  Scenario scenario = Scenario::IndoorUnknown;
  BackendMode mode = BackendMode::None;
  bool gps_available = false;
  bool map_available = false;
  std::string backend_status = "ok";  ///< "ok", or why the backend failed on this frame
  std::optional<PoseArray> estimated_pose;
  std::optional<PoseArray> ground_truth_pose;
  std::int64_t frontend_host_ns = 0;
  std::int64_t backend_host_ns = 0;
  bool operator==(const FrameRecord&) const = default;
};

/// Everything recorded for one frame.
struct FrameTrace {
  FrameRecord frame;
  std::vector<TaskRecord> tasks;
  std::vector<KernelRecord> kernels;
  bool operator==(const FrameTrace&) const = default;
};

/// Run-level metadata (the meta table): free key/value text. Required keys are listed in
/// docs/TRACE.md and checked by the reader; schema_version is written by the writer itself.
using TraceMeta = std::map<std::string, std::string>;

// Names used in the database, and their parsers (throw std::invalid_argument on unknown text).
const char* to_string(Task task);
const char* to_string(Image image);
const char* to_string(Scenario scenario);
const char* to_string(BackendMode mode);
const char* to_string(Op op);
const char* to_string(Precision precision);
Task parse_task(const std::string& text);
Image parse_image(const std::string& text);
Scenario parse_scenario(const std::string& text);
BackendMode parse_backend_mode(const std::string& text);
Op parse_op(const std::string& text);
Precision parse_precision(const std::string& text);

/// The kernels the backends compute at the trace's precision (docs/TRACE.md, "Precision"); the
/// others always compute in double.
inline constexpr std::array<const char*, 5> kKernelsAtTracePrecision = {
    "projection", "kalman_gain", "covariance_update", "gps_fusion", "marginalization"};
/// Whether `kernel` is one of kKernelsAtTracePrecision.
bool computed_at_trace_precision(const std::string& kernel);

/// Bytes of one scalar at `precision` (8 or 4).
constexpr int scalar_bytes(Precision precision) { return precision == Precision::kFp32 ? 4 : 8; }

/// The trace's precision (meta `precision`; docs/TRACE.md). Throws std::invalid_argument when
/// the key is absent or not fp64|fp32.
Precision trace_precision(const TraceMeta& meta);

}  // namespace edx::trace
