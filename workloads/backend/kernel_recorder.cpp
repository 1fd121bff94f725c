#include "workloads/backend/kernel_recorder.hpp"

#include <stdexcept>

namespace edx::backend {

KernelRecorder::Scope::Scope(KernelRecorder& recorder, std::size_t index)
    : recorder_(recorder), index_(index), start_ns_(now_ns()) {}

KernelRecorder::Scope::~Scope() {
  recorder_.kernels_[index_].host_ns = now_ns() - start_ns_;
  recorder_.open_ = false;
}

trace::KernelRecord& KernelRecorder::Scope::record() { return recorder_.kernels_[index_]; }

KernelRecorder::Scope KernelRecorder::kernel(std::string name, bool accelerable) {
  if (open_) throw std::logic_error("KernelRecorder: kernel '" + name + "' started inside another");
  trace::KernelRecord record;
  record.kernel = std::move(name);
  record.accelerable = accelerable;
  kernels_.push_back(std::move(record));
  open_ = true;
  return Scope(*this, kernels_.size() - 1);
}

void KernelRecorder::describe(trace::Op op, std::int64_t m, std::int64_t n, std::int64_t k,
                              std::uint32_t flags, std::int64_t batch) {
  if (!open_) throw std::logic_error("KernelRecorder: op outside a kernel");
  if (batch < 1) throw std::logic_error("KernelRecorder: an op batch of less than 1");
  kernels_.back().ops.push_back(trace::OpRecord{op, m, n, k, flags, 0, batch});
}

std::vector<trace::KernelRecord> KernelRecorder::take() {
  if (open_) throw std::logic_error("KernelRecorder: take() while a kernel is open");
  return std::exchange(kernels_, {});
}

KernelRecorder::OpTimer::OpTimer(KernelRecorder& recorder, trace::OpRecord record)
    : recorder_(recorder), record_(record), start_ns_(0) {
  if (!recorder_.open_) throw std::logic_error("KernelRecorder: op outside a kernel");
  start_ns_ = now_ns();
}

KernelRecorder::OpTimer::~OpTimer() {
  record_.host_ns = now_ns() - start_ns_;
  recorder_.kernels_.back().ops.push_back(record_);
}

}  // namespace edx::backend
