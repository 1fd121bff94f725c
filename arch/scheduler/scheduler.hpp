#pragma once
// The runtime offload scheduler of the paper's Sec. VI-B: per invocation of an accelerable
// backend kernel, run it on the host or offload it to the backend accelerator.
//
// Policies:
//   never       always on the host (the CPU-only baseline of the backend)
//   always      always offloaded (unless the accelerator cannot run it: an op no unit serves)
//   regression  offload when the host time predicted by a model of the kernel's size exceeds the
//               accelerator time estimated from the units' latency profiles plus the transfers;
//               each kernel's model is fit on the frames holding the first `training_fraction`
//               of that kernel's own invocations (linear for projection in map points, quadratic
//               for kalman_gain in H's rows and for marginalization in landmarks); those training
//               invocations themselves run on the host
//   oracle      offload exactly when the accelerator (with transfers) is faster
#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "arch/scheduler/regression.hpp"

namespace edx::arch {

enum class OffloadPolicy { kNever, kAlways, kRegression, kOracle };

/// never | always | regression | oracle; anything else throws std::runtime_error listing them.
OffloadPolicy parse_offload_policy(std::string_view text);
const char* to_string(OffloadPolicy policy);

/// Degree of the host-time model of an accelerable kernel (Sec. VI-B): projection 1,
/// kalman_gain 2, marginalization 2. Throws std::runtime_error for another kernel name.
int model_degree(const std::string& kernel);

/// One invocation of an accelerable kernel as the scheduler sees it.
struct KernelInvocation {
  std::size_t frame_index = 0;  ///< position of its frame in the trace
  std::string kernel;
  double size = 0;              ///< the kernel's size feature (its trace row's m)
  double host_s = 0;            ///< host time on the target CPU
  double accel_s = 0;           ///< accelerator time with transfers, as the model simulates it
  double accel_estimate_s = 0;  ///< the scheduler's estimate (unit profiles + transfer time)
};

class OffloadScheduler {
 public:
  /// `training_fraction` in [0, 1): the leading share of each kernel's invocations the models
  /// are fitted on (paper Sec. VII-A: 25 % of the frames of the datasets).
  OffloadScheduler(OffloadPolicy policy, double training_fraction);

  /// Splits every kernel's invocations (any policy): with N invocations of a kernel in frame
  /// order, its training frames are those up to and including the frame of its ⌈f·N⌉-th
  /// invocation, so that each kernel is profiled on the first share of its own invocations (of
  /// its own mode's frames) whatever the order of the modes in the trace. Then, for the
  /// regression policy, fits one model per kernel on its training invocations (a kernel with
  /// too few training samples for its degree keeps no model and is then never offloaded).
  void train(const std::vector<KernelInvocation>& invocations);

  /// The decision for one invocation.
  bool offload(const KernelInvocation& invocation) const;

  /// True for the invocations the models were trained on (after `train`; a kernel `train` has
  /// not seen has no training invocations).
  bool in_training(const KernelInvocation& invocation) const;
  OffloadPolicy policy() const { return policy_; }
  /// The first frame index after a kernel's training frames (0 for a kernel `train` has not
  /// seen).
  std::size_t training_end_frame(const std::string& kernel) const;
  const std::map<std::string, PolynomialModel>& models() const { return models_; }
  /// offload(invocation) given its kernel's training_end_frame and model (nullptr: none), found
  /// by the caller once per kernel.
  bool offload(const KernelInvocation& invocation, std::size_t training_end,
               const PolynomialModel* model) const;

 private:
  OffloadPolicy policy_;
  double training_fraction_ = 0;
  std::map<std::string, std::size_t> training_end_;  ///< per kernel: first evaluation frame
  std::map<std::string, PolynomialModel> models_;
};

/// The scheduler's effect on one kernel over the evaluation frames (those after training).
struct KernelScheduleSummary {
  std::string kernel;
  std::size_t invocations = 0;
  std::size_t offloaded = 0;
  double host_only_s = 0;            ///< every invocation on the host
  double always_s = 0;               ///< every invocation offloaded
  double policy_s = 0;               ///< as the policy decided
  double oracle_s = 0;               ///< as the oracle decides
  std::size_t training_samples = 0;  ///< invocations in the training frames
  bool has_model = false;            ///< regression: enough training samples for the model's degree
  double r_squared_train = 0;        ///< the model on its training samples (regression policy)
  double r_squared_eval = 0;         ///< the model on the evaluation samples
  double gap_to_oracle = 0;          ///< policy_s / oracle_s − 1
  nlohmann::json to_json() const;
};

/// One invocation's place in the schedule: in the training frames, and the decision.
struct ScheduleDecision {
  bool training = false;   ///< OffloadScheduler::in_training
  bool offloaded = false;  ///< OffloadScheduler::offload
};

/// Trains `scheduler` on `invocations` and summarizes every kernel over the evaluation frames;
/// with `decisions`, also each invocation's (in order), as the trained scheduler gives them.
std::vector<KernelScheduleSummary> evaluate_schedule(
    OffloadScheduler& scheduler, const std::vector<KernelInvocation>& invocations,
    std::vector<ScheduleDecision>* decisions = nullptr);

}  // namespace edx::arch
