// Regression models and offload policies on hand-computed data.
#include "arch/scheduler/scheduler.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <stdexcept>
#include <string>

namespace edx::arch {
namespace {

TEST(Regression, LinearLeastSquaresByHand) {
  // x 0..3, y 1 3 2 5: slope = 5.5 / 5 = 1.1, intercept = 2.75 - 1.1 * 1.5 = 1.1;
  // residuals -0.1 0.8 -1.3 0.6: SS_res = 2.7, SS_tot = 8.75, R² = 1 - 2.7 / 8.75.
  const PolynomialModel m = fit_polynomial({0, 1, 2, 3}, {1, 3, 2, 5}, 1);
  ASSERT_EQ(m.coefficients.size(), 2u);
  EXPECT_NEAR(m.coefficients[0], 1.1, 1e-12);
  EXPECT_NEAR(m.coefficients[1], 1.1, 1e-12);
  EXPECT_NEAR(m.r_squared, 1.0 - 2.7 / 8.75, 1e-12);
  EXPECT_NEAR(m.predict(10), 12.1, 1e-10);
}

TEST(Regression, QuadraticIsRecoveredExactlyAtLargeSizes) {
  std::vector<double> x, y;
  for (int i = 0; i < 20; ++i) {
    x.push_back(100.0 * i);
    y.push_back(2e-3 + 3e-6 * x.back() + 4e-9 * x.back() * x.back());
  }
  const PolynomialModel m = fit_polynomial(x, y, 2);
  EXPECT_NEAR(m.coefficients[0], 2e-3, 1e-12);
  EXPECT_NEAR(m.coefficients[1], 3e-6, 1e-14);
  EXPECT_NEAR(m.coefficients[2], 4e-9, 1e-16);
  EXPECT_NEAR(m.r_squared, 1.0, 1e-12);
  // Two samples at x = 50, one on the model and one 1 above: SS_res = 1, SS_tot = 2 * (1/2)² =
  // 0.5, R² = 1 - 1 / 0.5 = -1.
  EXPECT_NEAR(r_squared(m, {50, 50}, {m.predict(50), m.predict(50) + 1}), -1.0, 1e-9);
  // Times without variance up to rounding (modeled host times of one size): R² is undefined,
  // 1 when the model hits them and 0 when it misses, not -1e28 from a variance of 1e-34.
  const double t = m.predict(50);
  EXPECT_EQ(r_squared(m, {50, 50, 50}, {t, std::nextafter(t, 1.0), t}), 1.0);
  EXPECT_EQ(r_squared(m, {50, 50, 50}, {1.1 * t, std::nextafter(1.1 * t, 1.0), 1.1 * t}), 0.0);
}

TEST(Regression, TooFewOrBadSamplesAreErrors) {
  EXPECT_THROW(fit_polynomial({1, 2}, {1, 2}, 2), std::runtime_error);
  EXPECT_THROW(fit_polynomial({1, 2, 3}, {1, 2}, 1), std::runtime_error);
  EXPECT_THROW(fit_polynomial({1, 2, std::nan("")}, {1, 2, 3}, 1), std::runtime_error);
}

/// Marginalization invocations, one per frame, host time 1e-8·size², accelerator 1e-4 s: the
/// oracle offloads sizes above 100.
std::vector<KernelInvocation> invocations(std::size_t frames) {
  std::vector<KernelInvocation> out;
  for (std::size_t f = 0; f < frames; ++f) {
    KernelInvocation k;
    k.frame_index = f;
    k.kernel = "marginalization";
    k.size = static_cast<double>((f * 37) % 200);
    k.host_s = 1e-8 * k.size * k.size;
    k.accel_s = k.accel_estimate_s = 1e-4;
    out.push_back(k);
  }
  return out;
}

TEST(OffloadScheduler, RegressionMatchesTheOracleWhenTheModelIsExact) {
  const auto all = invocations(400);
  OffloadScheduler regression(OffloadPolicy::kRegression, 0.25);
  const auto summary = evaluate_schedule(regression, all);
  ASSERT_EQ(summary.size(), 1u);
  const KernelScheduleSummary& s = summary[0];
  // One invocation a frame: the first ⌈0.25 · 400⌉ = 100 invocations are frames 0..99.
  EXPECT_EQ(regression.training_end_frame("marginalization"), 100u);
  EXPECT_EQ(s.training_samples, 100u);
  EXPECT_EQ(s.invocations, 300u);
  EXPECT_NEAR(s.r_squared_train, 1.0, 1e-9);
  EXPECT_NEAR(s.gap_to_oracle, 0.0, 1e-9);
  std::size_t expected_offloads = 0;
  for (const auto& k : all) {
    if (k.frame_index >= 100 && k.size > 100) ++expected_offloads;
  }
  EXPECT_EQ(s.offloaded, expected_offloads);
  EXPECT_LT(s.policy_s, s.host_only_s);
  EXPECT_LT(s.policy_s, s.always_s);  // small sizes are faster on the host
}

TEST(OffloadScheduler, FixedPoliciesAndTrainingFrames) {
  const auto all = invocations(100);
  OffloadScheduler never(OffloadPolicy::kNever, 0.25);
  const auto n = evaluate_schedule(never, all)[0];
  EXPECT_EQ(n.offloaded, 0u);
  EXPECT_DOUBLE_EQ(n.policy_s, n.host_only_s);
  OffloadScheduler always(OffloadPolicy::kAlways, 0.25);
  const auto a = evaluate_schedule(always, all)[0];
  EXPECT_EQ(a.offloaded, a.invocations);
  EXPECT_DOUBLE_EQ(a.policy_s, a.always_s);
  OffloadScheduler regression(OffloadPolicy::kRegression, 0.25);
  regression.train(all);
  EXPECT_FALSE(regression.offload(all[3]));  // a training frame runs on the host
  EXPECT_THROW(OffloadScheduler(OffloadPolicy::kOracle, 1.0), std::runtime_error);
  EXPECT_THROW(parse_offload_policy("sometimes"), std::runtime_error);
  EXPECT_EQ(parse_offload_policy("oracle"), OffloadPolicy::kOracle);
  EXPECT_THROW(model_degree("pnp"), std::runtime_error);
}

/// A mixed trace as the paper's mix orders it: frames 0..199 VIO (one kalman_gain a frame),
/// 200..299 SLAM (a marginalization on every other frame), 300..399 registration (one
/// projection a frame). Host times follow each kernel's model degree exactly.
std::vector<KernelInvocation> mixed_invocations() {
  std::vector<KernelInvocation> out;
  const auto add = [&](std::size_t f, const char* kernel, double size, double host_s) {
    KernelInvocation k;
    k.frame_index = f;
    k.kernel = kernel;
    k.size = size;
    k.host_s = host_s;
    k.accel_s = k.accel_estimate_s = 1e-4;
    out.push_back(k);
  };
  for (std::size_t f = 0; f < 200; ++f) {
    const double m = double(20 + f % 50);
    add(f, "kalman_gain", m, 1e-5 + 1e-7 * m * m);
  }
  for (std::size_t f = 200; f < 300; f += 2) {
    const double m = double(10 + (f * 7) % 300);
    add(f, "marginalization", m, 2e-5 + 3e-9 * m * m);
  }
  for (std::size_t f = 300; f < 400; ++f) {
    const double m = double(1000 + 40 * (f % 25));
    add(f, "projection", m, 5e-6 + 3e-8 * m);
  }
  return out;
}

TEST(OffloadScheduler, EachKernelTrainsOnTheFirstQuarterOfItsOwnInvocations) {
  const auto all = mixed_invocations();
  OffloadScheduler regression(OffloadPolicy::kRegression, 0.25);
  const auto summary = evaluate_schedule(regression, all);
  ASSERT_EQ(summary.size(), 3u);  // by kernel name
  // kalman_gain: 200 invocations, ⌈50⌉ -> frames 0..49; marginalization: 50 invocations on
  // frames 200, 202, ..., ⌈12.5⌉ = 13 -> up to frame 224; projection: 100, 25 -> frames 300..324.
  EXPECT_EQ(regression.training_end_frame("kalman_gain"), 50u);
  EXPECT_EQ(regression.training_end_frame("marginalization"), 225u);
  EXPECT_EQ(regression.training_end_frame("projection"), 325u);
  EXPECT_EQ(regression.training_end_frame("pnp"), 0u);  // never seen: no training frames
  // 0.14 x 50 is 7.000000000000001 in doubles: still 7 training invocations (frames 0..6).
  OffloadScheduler share(OffloadPolicy::kNever, 0.14);
  share.train(std::vector<KernelInvocation>(all.begin(), all.begin() + 50));
  EXPECT_EQ(share.training_end_frame("kalman_gain"), 7u);
  const std::map<std::string, std::pair<std::size_t, std::size_t>> expected = {
      {"kalman_gain", {50, 150}}, {"marginalization", {13, 37}}, {"projection", {25, 75}}};
  for (const KernelScheduleSummary& s : summary) {
    SCOPED_TRACE(s.kernel);
    EXPECT_EQ(s.training_samples, expected.at(s.kernel).first);
    EXPECT_EQ(s.invocations, expected.at(s.kernel).second);
    ASSERT_TRUE(s.has_model);  // a frame-based 25 % split would leave two kernels without one
    EXPECT_NEAR(s.r_squared_train, 1.0, 1e-9);
    EXPECT_NEAR(s.gap_to_oracle, 0.0, 1e-9);
  }
  // Training invocations run on the host; the first evaluation one is decided by the model.
  KernelInvocation k = all[0];
  EXPECT_TRUE(regression.in_training(k));
  EXPECT_FALSE(regression.offload(k));
  k.frame_index = 300;  // a kalman_gain after its training frames
  EXPECT_FALSE(regression.in_training(k));
  k.size = 69;  // host 1e-5 + 1e-7 · 69² = 4.86e-4 s > 1e-4 s on the accelerator
  EXPECT_TRUE(regression.offload(k));
  k.size = 20;  // host 5e-5 s < 1e-4 s
  EXPECT_FALSE(regression.offload(k));
}

TEST(OffloadScheduler, EvaluationGivesEachInvocationsDecisionAsTheTrainedScheduler) {
  // The mixed trace, each policy: the decisions evaluate_schedule gives equal in_training and
  // offload of the trained scheduler, invocation by invocation.
  const auto all = mixed_invocations();
  for (OffloadPolicy policy : {OffloadPolicy::kRegression, OffloadPolicy::kAlways,
                               OffloadPolicy::kNever, OffloadPolicy::kOracle}) {
    SCOPED_TRACE(to_string(policy));
    OffloadScheduler scheduler(policy, 0.25);
    std::vector<ScheduleDecision> decided;
    const auto summary = evaluate_schedule(scheduler, all, &decided);
    ASSERT_EQ(decided.size(), all.size());
    std::size_t training = 0, offloaded = 0;
    for (std::size_t i = 0; i < all.size(); ++i) {
      EXPECT_EQ(decided[i].training, scheduler.in_training(all[i])) << i;
      EXPECT_EQ(decided[i].offloaded, scheduler.offload(all[i])) << i;
      training += decided[i].training ? 1 : 0;
      offloaded += decided[i].offloaded && !decided[i].training ? 1 : 0;
    }
    EXPECT_EQ(training, 50u + 13u + 25u);
    std::size_t summarized = 0;
    for (const KernelScheduleSummary& s : summary) summarized += s.offloaded;
    EXPECT_EQ(summarized, offloaded);
  }
  // A kernel whose invocations are all training ones (one invocation: ⌈0.25⌉ = 1) is not
  // summarized; its decision is still given.
  OffloadScheduler regression(OffloadPolicy::kRegression, 0.25);
  std::vector<KernelInvocation> one(all.begin(), all.begin() + 1);
  std::vector<ScheduleDecision> decided;
  EXPECT_TRUE(evaluate_schedule(regression, one, &decided).empty());
  ASSERT_EQ(decided.size(), 1u);
  EXPECT_TRUE(decided[0].training);
  EXPECT_FALSE(decided[0].offloaded);
}

}  // namespace
}  // namespace edx::arch
