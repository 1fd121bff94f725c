#pragma once
// Instrumentation of backend kernels for the trace (docs/TRACE.md, kernels and ops tables):
// each kernel invocation is timed on the host by the thread's CPU time (host_clock.hpp), and inside
// the accelerable kernels every matrix primitive is timed and recorded with its dimensions and
// structure flags.
//
//   KernelRecorder rec;
//   {
//     auto k = rec.kernel("kalman_gain", /*accelerable=*/true);
//     k.record().m = H.rows(); k.record().n = H.cols();
//     Eigen::MatrixXd S = rec.op(trace::Op::Gemm, m, n, k, 0, [&] { return (H * PHt).eval(); });
//   }  // host_ns of the kernel is set here
//   out.kernels = rec.take();
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "workloads/trace/host_clock.hpp"
#include "workloads/trace/records.hpp"

namespace edx::backend {

class KernelRecorder {
 public:
  /// A running kernel; its host time is the time from creation to destruction.
  class Scope {
   public:
    ~Scope();
    Scope(const Scope&) = delete;
    Scope& operator=(const Scope&) = delete;
    /// The kernel's record, to fill in sizes (m, n, k, detail_json).
    trace::KernelRecord& record();

   private:
    friend class KernelRecorder;
    Scope(KernelRecorder& recorder, std::size_t index);
    KernelRecorder& recorder_;
    std::size_t index_;
    std::int64_t start_ns_;
  };

  /// Starts a kernel invocation. Kernels do not nest: starting one while another is open
  /// throws std::logic_error.
  [[nodiscard]] Scope kernel(std::string name, bool accelerable = false);

  /// Runs `fn`, timing it, and records it as a matrix primitive of the open kernel. Returns
  /// what `fn` returns (make it return an evaluated Eigen object, not an expression). Throws
  /// std::logic_error when no kernel is open.
  template <class Fn>
  decltype(auto) op(trace::Op op, std::int64_t m, std::int64_t n, std::int64_t k,
                    std::uint32_t flags, Fn&& fn) {
    OpTimer timer(*this, trace::OpRecord{op, m, n, k, flags, 0});
    return std::forward<Fn>(fn)();
  }

  /// Records a matrix primitive of the open kernel without running or timing anything (host_ns
  /// 0): the dense primitive a kernel's work amounts to where the host computes it another way
  /// (SLAM's Schur complement exploits its block sparsity in loops; docs/TRACE.md, ops table).
  /// `batch` independent instances of the op (per-feature products: one record for them all).
  /// Throws std::logic_error when no kernel is open.
  void describe(trace::Op op, std::int64_t m, std::int64_t n, std::int64_t k, std::uint32_t flags,
                std::int64_t batch = 1);

  /// The kernels recorded since the last take(), in order; clears them. Throws
  /// std::logic_error while a kernel is open.
  std::vector<trace::KernelRecord> take();

  /// The recording thread's CPU time in ns (workloads/trace/host_clock.hpp).
  static std::int64_t now_ns() { return trace::thread_cpu_ns(); }

 private:
  class OpTimer {
   public:
    OpTimer(KernelRecorder& recorder, trace::OpRecord record);
    ~OpTimer();
    OpTimer(const OpTimer&) = delete;
    OpTimer& operator=(const OpTimer&) = delete;

   private:
    KernelRecorder& recorder_;
    trace::OpRecord record_;
    std::int64_t start_ns_;
  };

  std::vector<trace::KernelRecord> kernels_;
  bool open_ = false;
};

}  // namespace edx::backend
