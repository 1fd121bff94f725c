#include "arch/scheduler/scheduler.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "arch/kernels/kernels.hpp"

namespace edx::arch {

OffloadPolicy parse_offload_policy(std::string_view text) {
  if (text == "never") return OffloadPolicy::kNever;
  if (text == "always") return OffloadPolicy::kAlways;
  if (text == "regression") return OffloadPolicy::kRegression;
  if (text == "oracle") return OffloadPolicy::kOracle;
  throw std::runtime_error(fmt::format(
      "unknown offload policy '{}' (expected never, always, regression or oracle)", text));
}

const char* to_string(OffloadPolicy policy) {
  switch (policy) {
    case OffloadPolicy::kNever:
      return "never";
    case OffloadPolicy::kAlways:
      return "always";
    case OffloadPolicy::kRegression:
      return "regression";
    case OffloadPolicy::kOracle:
      return "oracle";
  }
  return "?";
}

int model_degree(const std::string& kernel) {
  const AccelerableKernel* descriptor = find_accelerable_kernel(kernel);
  if (descriptor == nullptr) {
    throw std::runtime_error(fmt::format("no host-time model for kernel '{}' (expected {})", kernel,
                                         accelerable_kernel_names()));
  }
  return descriptor->host_model_degree;
}

OffloadScheduler::OffloadScheduler(OffloadPolicy policy, double training_fraction)
    : policy_(policy), training_fraction_(training_fraction) {
  if (!(training_fraction >= 0 && training_fraction < 1)) {
    throw std::runtime_error(fmt::format(
        "scheduler.training_fraction: expected a fraction in [0, 1), got {}", training_fraction));
  }
}

bool OffloadScheduler::in_training(const KernelInvocation& invocation) const {
  return invocation.frame_index < training_end_frame(invocation.kernel);
}

std::size_t OffloadScheduler::training_end_frame(const std::string& kernel) const {
  const auto it = training_end_.find(kernel);
  return it == training_end_.end() ? 0 : it->second;
}

void OffloadScheduler::train(const std::vector<KernelInvocation>& invocations) {
  models_.clear();
  training_end_.clear();
  std::map<std::string, std::vector<std::size_t>> frames_of;
  for (const KernelInvocation& k : invocations) frames_of[k.kernel].push_back(k.frame_index);
  for (auto& [kernel, frames] : frames_of) {
    std::sort(frames.begin(), frames.end());
    // ⌈f·N⌉, immune to f·N landing a rounding error above an integer (0.14 x 50).
    const auto n_train = static_cast<std::size_t>(
        std::ceil(training_fraction_ * static_cast<double>(frames.size()) - 1e-9));
    training_end_[kernel] = n_train == 0 ? 0 : frames[n_train - 1] + 1;
  }
  if (policy_ != OffloadPolicy::kRegression) return;
  std::map<std::string, std::pair<std::vector<double>, std::vector<double>>> samples;
  for (const KernelInvocation& k : invocations) {
    if (!in_training(k)) continue;
    samples[k.kernel].first.push_back(k.size);
    samples[k.kernel].second.push_back(k.host_s);
  }
  for (const auto& [kernel, xy] : samples) {
    const int degree = model_degree(kernel);
    if (xy.first.size() < static_cast<std::size_t>(degree) + 1) continue;
    models_[kernel] = fit_polynomial(xy.first, xy.second, degree);
  }
}

bool OffloadScheduler::offload(const KernelInvocation& k) const {
  if (policy_ != OffloadPolicy::kRegression) return offload(k, 0, nullptr);
  const auto it = models_.find(k.kernel);
  return offload(k, training_end_frame(k.kernel), it != models_.end() ? &it->second : nullptr);
}

bool OffloadScheduler::offload(const KernelInvocation& k, std::size_t training_end,
                               const PolynomialModel* model) const {
  switch (policy_) {
    case OffloadPolicy::kNever:
      return false;
    case OffloadPolicy::kAlways:
      return std::isfinite(k.accel_s);  // a kernel no unit can run stays on the host
    case OffloadPolicy::kOracle:
      return k.accel_s < k.host_s;
    case OffloadPolicy::kRegression:
      if (k.frame_index < training_end) return false;  // profiled on the host
      return model != nullptr && model->predict(k.size) > k.accel_estimate_s;
  }
  return false;
}

nlohmann::json KernelScheduleSummary::to_json() const {
  return {{"kernel", kernel},
          {"invocations", invocations},
          {"offloaded", offloaded},
          {"host_only_s", host_only_s},
          {"always_s", always_s},
          {"policy_s", policy_s},
          {"oracle_s", oracle_s},
          {"training_samples", training_samples},
          {"has_model", has_model},
          {"r_squared_train", r_squared_train},
          {"r_squared_eval", r_squared_eval},
          {"gap_to_oracle", gap_to_oracle}};
}

std::vector<KernelScheduleSummary> evaluate_schedule(
    OffloadScheduler& scheduler, const std::vector<KernelInvocation>& invocations,
    std::vector<ScheduleDecision>* decisions) {
  scheduler.train(invocations);
  // Per kernel (found once per invocation): its training end and model, its summary over the
  // evaluation frames (a kernel appears once it has one) and their samples.
  struct Kernel {
    std::size_t training_end = 0;
    const PolynomialModel* model = nullptr;
    std::size_t training_samples = 0;
    KernelScheduleSummary summary;
    std::vector<double> sizes, host_s;
  };
  std::map<std::string, Kernel> kernels;
  if (decisions != nullptr) decisions->reserve(decisions->size() + invocations.size());
  for (const KernelInvocation& k : invocations) {
    const auto [it, added] = kernels.try_emplace(k.kernel);
    Kernel& kernel = it->second;
    if (added) {
      kernel.training_end = scheduler.training_end_frame(k.kernel);
      const auto model = scheduler.models().find(k.kernel);
      if (model != scheduler.models().end()) kernel.model = &model->second;
    }
    const bool training = k.frame_index < kernel.training_end;
    const bool off = scheduler.offload(k, kernel.training_end, kernel.model);
    if (decisions != nullptr) decisions->push_back({training, off});
    if (training) {
      ++kernel.training_samples;
      continue;
    }
    KernelScheduleSummary& s = kernel.summary;
    s.kernel = k.kernel;
    ++s.invocations;
    if (off) ++s.offloaded;
    s.host_only_s += k.host_s;
    s.always_s += k.accel_s;
    s.policy_s += off ? k.accel_s : k.host_s;
    s.oracle_s += std::min(k.accel_s, k.host_s);
    kernel.sizes.push_back(k.size);
    kernel.host_s.push_back(k.host_s);
  }
  std::vector<KernelScheduleSummary> out;
  for (auto& [name, kernel] : kernels) {
    KernelScheduleSummary& s = kernel.summary;
    if (s.invocations == 0) continue;  // every invocation in training: not evaluated
    s.training_samples = kernel.training_samples;
    s.has_model = kernel.model != nullptr;
    if (s.has_model) {
      s.r_squared_train = kernel.model->r_squared;
      s.r_squared_eval = r_squared(*kernel.model, kernel.sizes, kernel.host_s);
    }
    s.gap_to_oracle = s.oracle_s > 0 ? s.policy_s / s.oracle_s - 1.0 : 0.0;
    out.push_back(s);
  }
  return out;
}

}  // namespace edx::arch
