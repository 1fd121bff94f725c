// edx report / edx check on a small hand-made results database written through the results_db
// writer (arch/results/results_db.hpp), with figures computed by hand.
#include <SQLiteCpp/SQLiteCpp.h>
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "arch/memory/bram.hpp"
#include "arch/platform/platform.hpp"
#include "arch/results/results_db.hpp"
#include "arch/results/schema.hpp"
#include "arch/system/result_rows.hpp"
#include "arch/system/system_model.hpp"
#include "reports/html_report.hpp"
#include "reports/metrics.hpp"
#include "reports/paper_check.hpp"
#include "reports/results_reader.hpp"
#include "tests/support/run_command.hpp"
#include "tests/support/temp_dir.hpp"
#include "workloads/trace/schema.hpp"
#include "workloads/trace/writer.hpp"

namespace edx::reports {
namespace {

using edx::testing::TempDir;

arch::Distribution dist(double mean, double sd) {
  arch::Distribution d;
  d.count = 2;
  d.mean = d.p50 = mean;
  d.sd = sd;
  d.rsd = sd / mean;
  d.p90 = d.p99 = d.max = mean + sd;
  return d;
}

arch::FrameResult frame(std::int64_t id, const std::string& mode, double fe, double be,
                        double energy) {
  arch::FrameResult f;
  f.frame_id = id;
  f.mode = mode;
  f.frontend_ms = fe;
  f.backend_ms = be;
  f.e2e_ms = fe + be;
  f.host_busy_ms = fe + be;
  f.energy.total_j = energy;
  return f;
}

/// Two VIO frames and two SLAM frames. Baseline e2e means 100 ms, accelerated 50 ms (speedup
/// 2.0); kalman_gain: host 4 + 2 ms, accelerator 1 + 1 ms (speedup 3.0); marginalization offloaded
/// 3 of 4 evaluated invocations (0.75); always-offload 0.33 s against a policy 0.30 s (+10%).
arch::SystemResult hand_made() {
  arch::SystemResult r;
  r.config = arch::Platform::load(std::string(EDX_SOURCE_DIR) + "/configs/edx_car.yaml");
  r.platform = "hand_made";
  r.config_hash = "00000000000000aa";
  r.trace_hash = "00000000000000bb";
  r.trace_path = "hand_made.db";
  r.baseline.variant = "baseline";
  r.accelerated.variant = "accelerated";
  r.baseline.frames = {frame(0, "vio", 60, 20, 1.5), frame(1, "vio", 60, 30, 1.6),
                       frame(2, "slam", 70, 40, 2.0), frame(3, "slam", 70, 50, 2.1)};
  r.accelerated.frames = {frame(0, "vio", 30, 10, 0.4), frame(1, "vio", 30, 15, 0.5),
                          frame(2, "slam", 30, 20, 0.6), frame(3, "slam", 30, 45, 0.7)};
  for (auto* v : {&r.baseline, &r.accelerated}) {
    const bool base = v == &r.baseline;
    arch::ModeSummary all;
    all.frames = 4;
    all.e2e_ms = dist(base ? 100 : 50, base ? 20 : 10);
    all.frontend_ms = dist(base ? 65 : 30, 5);
    all.backend_ms = dist(base ? 35 : 20, 10);
    all.energy_j = dist(base ? 1.8 : 0.55, 0.1);
    v->modes["all"] = all;
    v->modes["vio"] = all;
    v->modes["slam"] = all;
    v->fps_without_pipelining = base ? 10 : 20;
    v->fps_with_pipelining = base ? 12 : 30;
  }
  const auto decision = [](std::int64_t frame_id, int seq, const char* kernel, double host,
                           double accel, bool offloaded) {
    arch::KernelDecision d;
    d.frame_id = frame_id;
    d.kernel_seq = seq;
    d.kernel = kernel;
    d.size = 10;
    d.host_ms = host;
    d.accel_ms = accel;
    d.compute_ms = accel;
    d.offloaded = offloaded;
    return d;
  };
  r.decisions = {decision(0, 0, "kalman_gain", 4, 1, true),
                 decision(1, 0, "kalman_gain", 2, 1, true),
                 decision(2, 0, "marginalization", 8, 4, true),
                 decision(3, 0, "marginalization", 8, 4, false)};
  arch::KernelScheduleSummary s;
  s.kernel = "marginalization";
  s.invocations = 4;
  s.offloaded = 3;
  s.host_only_s = 0.4;
  s.always_s = 0.33;
  s.policy_s = 0.30;
  s.oracle_s = 0.29;
  s.r_squared_eval = 0.9;
  r.schedule = {s};
  return r;
}

std::filesystem::path write_targets(const std::filesystem::path& dir, const std::string& text) {
  const std::filesystem::path path = dir / "targets.yaml";
  std::ofstream(path) << text;
  return path;
}

TEST(ResultsReader, ReadsTheRunWrittenByTheWriter) {
  TempDir dir;
  arch::write_results(dir.path() / "r.db", arch::result_rows(hand_made()));
  const ResultsData data = read_results(dir.path() / "r.db");
  ASSERT_EQ(data.runs.size(), 1u);
  const RunData& run = data.runs[0];
  EXPECT_EQ(run.run_id, "00000000000000aa-00000000000000bb");
  EXPECT_EQ(run.frame_rows.size(), 8u);
  EXPECT_EQ(run.offload.size(), 4u);
  EXPECT_FALSE(data.has_sweeps);
  const nlohmann::json m = run_metrics(run);
  EXPECT_DOUBLE_EQ(*metric_at(m, "system.comparison.all.e2e_speedup"), 2.0);
  EXPECT_DOUBLE_EQ(*metric_at(m, "derived.kernels.kalman_gain.speedup"), 3.0);
  EXPECT_DOUBLE_EQ(*metric_at(m, "derived.kernels.marginalization.latency_reduction"), 0.5);
  EXPECT_DOUBLE_EQ(*metric_at(m, "derived.schedule.marginalization.offloaded_fraction"), 0.75);
  EXPECT_NEAR(*metric_at(m, "derived.schedule.marginalization.always_vs_policy"), 0.1, 1e-12);
  EXPECT_FALSE(metric_at(m, "frontend.fps_without_pipelining"));
  EXPECT_FALSE(metric_at(m, "system.comparison"));  // an object, not a number
  // Backend breakdown of the VIO frames: baseline kalman 3 ms/frame, other (20+30)/2 − 3 = 22;
  // accelerated kalman 1 ms/frame (both offloaded).
  for (const BackendBreakdown& b : backend_breakdown(run)) {
    if (b.mode != "vio") continue;
    std::map<std::string, double> parts(b.parts.begin(), b.parts.end());
    EXPECT_DOUBLE_EQ(parts["kalman_gain"], b.variant == "baseline" ? 3.0 : 1.0);
    EXPECT_DOUBLE_EQ(parts["other"], 22.0);
    EXPECT_DOUBLE_EQ(parts["marginalization"], 0.0);
  }
}

TEST(ResultsReader, ReadingAWalDatabaseLeavesNothingBesideIt) {
  // A database a sweep left in WAL mode: reading it (the report, check, explain; export alike)
  // must not leave the -wal and -shm files a read-only connection creates and cannot remove.
  TempDir dir;
  const std::filesystem::path db = dir.path() / "r.db";
  arch::write_results(db, arch::result_rows(hand_made()));
  SQLite::Database(db.string(), SQLite::OPEN_READWRITE).exec("PRAGMA journal_mode = WAL");
  ASSERT_FALSE(std::filesystem::exists(db.string() + "-wal"));
  EXPECT_EQ(read_results(db).runs.size(), 1u);
  EXPECT_FALSE(std::filesystem::exists(db.string() + "-wal"));
  EXPECT_FALSE(std::filesystem::exists(db.string() + "-shm"));
}

TEST(PaperCheck, VerdictsOnKnownValues) {
  TempDir dir;
  arch::write_results(dir.path() / "r.db", arch::result_rows(hand_made()));
  const std::filesystem::path yaml = write_targets(dir.path(), R"(tolerance: 0.10
targets:
  - {name: speedup near, metric: system.comparison.all.e2e_speedup, paper: 2.1}
  - {name: speedup far, metric: system.comparison.all.e2e_speedup, paper: 2.5}
  - {name: kernel, metric: derived.kernels.kalman_gain.speedup, paper: 3.0, tolerance: 0.01}
  - {name: offloaded, metric: derived.schedule.marginalization.offloaded_fraction, paper: 0.8}
  - {name: frontend fps, metric: frontend.fps_without_pipelining, paper: 26.1}
)");
  const std::vector<PaperTarget> targets = load_targets(yaml);
  ASSERT_EQ(targets.size(), 5u);
  EXPECT_EQ(targets[2].line, 5);
  const ResultsData data = read_results(dir.path() / "r.db");
  const CheckResult c = check_targets(targets, run_metrics(data.runs[0]), data.runs[0].run_id);
  ASSERT_EQ(c.rows.size(), 5u);
  EXPECT_EQ(c.rows[0].verdict, Verdict::kPass);  // 2.0 vs 2.1: −4.8%
  EXPECT_NEAR(c.rows[0].error, -0.1 / 2.1, 1e-12);
  EXPECT_EQ(c.rows[1].verdict, Verdict::kMiss);  // 2.0 vs 2.5: −20%
  EXPECT_NEAR(c.rows[1].error, -0.2, 1e-12);
  EXPECT_EQ(c.rows[2].verdict, Verdict::kPass);      // 3.0 exactly
  EXPECT_EQ(c.rows[3].verdict, Verdict::kPass);      // 0.75 vs 0.8: −6.25%
  EXPECT_EQ(c.rows[4].verdict, Verdict::kNotFound);  // not in a results database
  EXPECT_EQ(c.passed(), 3u);
  EXPECT_FALSE(c.all_passed());
  const std::string text = format_check(c);
  EXPECT_NE(text.find("not found in the results: frontend.fps_without_pipelining"),
            std::string::npos);
}

TEST(PaperCheck, AMetricsModeComesFromItsKeysOrItsKernel) {
  EXPECT_EQ(metric_mode("system.comparison.registration.e2e_speedup"), "registration");
  EXPECT_EQ(metric_mode("system.accelerated.modes.slam.e2e_ms.mean"), "slam");
  EXPECT_EQ(metric_mode("derived.backend.vio.baseline.other"), "vio");
  EXPECT_EQ(metric_mode("derived.kernels.kalman_gain.speedup"), "vio");  // arch/kernels
  EXPECT_EQ(metric_mode("derived.schedule.projection.r_squared_eval"), "registration");
  EXPECT_EQ(metric_mode("derived.schedule.marginalization.offloaded_fraction"), "slam");
  EXPECT_FALSE(metric_mode("system.comparison.all.e2e_speedup"));
  EXPECT_FALSE(metric_mode("system.baseline.modes.all.energy_j.mean"));
  EXPECT_FALSE(metric_mode("derived.kernels.no_such_kernel.speedup"));
  EXPECT_FALSE(metric_mode("system.resources.total.lut"));
  EXPECT_FALSE(metric_mode("baselines.single_core.speedup"));
  EXPECT_FALSE(metric_mode("frontend.fps_without_pipelining"));
}

TEST(PaperCheck, TargetsOfModesTheRunHasNoFramesOfAreNotApplicable) {
  TempDir dir;
  arch::write_results(dir.path() / "r.db", arch::result_rows(hand_made()));  // VIO and SLAM
  const std::filesystem::path yaml = write_targets(dir.path(), R"(targets:
  - {name: e2e speedup registration, metric: system.comparison.registration.e2e_speedup, paper: 2.5}
  - {name: projection, metric: derived.kernels.projection.latency_reduction, paper: 0.95}
  - {name: R2 registration, metric: derived.schedule.projection.r_squared_eval, paper: 0.83}
  - {name: registration e2e, metric: system.accelerated.modes.registration.e2e_ms.mean, paper: 9}
  - {name: e2e speedup VIO, metric: system.comparison.vio.e2e_speedup, paper: 2.0}
  - {name: R2 VIO, metric: derived.schedule.kalman_gain.r_squared_eval, paper: 0.82}
  - {name: overall, metric: system.comparison.all.e2e_speedup, paper: 2.0}
)");
  const std::vector<PaperTarget> targets = load_targets(yaml);
  const ResultsData data = read_results(dir.path() / "r.db");
  nlohmann::json metrics = run_metrics(data.runs[0]);
  const CheckResult c = check_targets(targets, metrics, data.runs[0].run_id);
  ASSERT_EQ(c.rows.size(), 7u);
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(c.rows[i].verdict, Verdict::kNotApplicable) << c.rows[i].target.name;
    EXPECT_EQ(c.rows[i].absent_mode, "registration");
    EXPECT_FALSE(c.rows[i].simulated);
  }
  EXPECT_EQ(c.rows[4].verdict, Verdict::kPass);
  // VIO has frames but no scheduler row of kalman_gain: a figure the run should have, missing.
  EXPECT_EQ(c.rows[5].verdict, Verdict::kNotFound);
  EXPECT_EQ(c.rows[6].verdict, Verdict::kPass);
  EXPECT_EQ(c.counted(), 3u);
  EXPECT_EQ(c.passed(), 2u);
  EXPECT_NE(format_check(c).find("4 n/a (the run has no frames of their mode: registration)"),
            std::string::npos);
  // Decided from the run's data: a tree without its per-mode summary cannot tell, so the
  // registration figures are simply not found.
  metrics["system"]["baseline"].erase("modes");
  const CheckResult unknown = check_targets(targets, metrics, data.runs[0].run_id);
  EXPECT_EQ(unknown.rows[0].verdict, Verdict::kNotFound);
  EXPECT_EQ(unknown.count(Verdict::kNotApplicable), 0u);
  // edx check: n/a rows do not fail it.
  const std::filesystem::path pass_and_na = write_targets(dir.path(), R"(targets:
  - {name: overall, metric: system.comparison.all.e2e_speedup, paper: 2.0}
  - {name: e2e speedup registration, metric: system.comparison.registration.e2e_speedup, paper: 2.5}
)");
  const std::string edx = edx::testing::built_binary("edx");
  const std::string db = (dir.path() / "r.db").string();
  auto ok = edx::testing::run_command(edx + " check --results " + db + " --targets " +
                                      pass_and_na.string());
  EXPECT_EQ(ok.exit_code, 0) << ok.out << ok.err;
  EXPECT_NE(ok.out.find("1 of 1 targets within tolerance; 1 n/a"), std::string::npos) << ok.out;
}

TEST(PaperCheck, CommandExitCodes) {
  TempDir dir;
  arch::write_results(dir.path() / "r.db", arch::result_rows(hand_made()));
  const std::string edx = edx::testing::built_binary("edx");
  const std::string db = (dir.path() / "r.db").string();
  const std::filesystem::path pass = write_targets(
      dir.path(), "targets:\n  - {name: s, metric: system.comparison.all.e2e_speedup, paper: 2}\n");
  auto ok = edx::testing::run_command(edx + " check --results " + db + " --targets " +
                                      pass.string() + " --json");
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_EQ(nlohmann::json::parse(ok.out)["rows"][0]["verdict"], "pass");
  // The shipped paper targets on this toy run: misses, exit 1, the table on stdout.
  auto miss = edx::testing::run_command(edx + " check --results " + db);
  EXPECT_EQ(miss.exit_code, 1);
  EXPECT_NE(miss.out.find("MISS"), std::string::npos);
  EXPECT_NE(miss.out.find("e2e speedup registration"), std::string::npos);
  auto bad =
      edx::testing::run_command(edx + " check --results " + dir.path().string() + "/missing.db");
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.err.find("missing.db: no such results database"), std::string::npos);
}

TEST(PaperCheck, ShippedTargetsAreValid) {
  const std::vector<PaperTarget> targets = load_targets(default_targets_path());
  EXPECT_GE(targets.size(), 30u);
  // ±10 % everywhere, but the characterization's orderings: 1 (edx's backend is the paper's) or
  // 0, checked exactly.
  for (const PaperTarget& t : targets) {
    EXPECT_DOUBLE_EQ(t.tolerance, t.metric.ends_with("_matches") ? 0.01 : 0.10) << t.name;
  }
  // Every explanation a target points to is an anchor of docs/MODEL.md.
  const std::string model = edx::testing::read_file(
      default_targets_path().parent_path().parent_path() / "docs" / "MODEL.md");
  std::size_t explained = 0;
  for (const PaperTarget& t : targets) {
    if (t.explained.empty()) continue;
    ++explained;
    EXPECT_NE(model.find("<a id=\"" + t.explained + "\"></a>"), std::string::npos)
        << t.name << ": docs/MODEL.md has no anchor " << t.explained;
  }
  EXPECT_GE(explained, 20u);
}

TEST(PaperCheck, BadYamlNamesFileLineAndKey) {
  TempDir dir;
  const auto error_of = [&](const std::string& text) {
    const std::filesystem::path yaml = write_targets(dir.path(), text);
    try {
      load_targets(yaml);
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string file = (dir.path() / "targets.yaml").string();
  EXPECT_EQ(error_of("targets:\n  - name: a\n    metric: x.y\n    paper: big\n"),
            file + ":4: paper: expected a number, got 'big'");
  EXPECT_EQ(error_of("targets:\n  - {name: a, metric: x, paper: 1, colour: red}\n"),
            file +
                ":2: colour: unknown key (expected name, metric, paper, unit, tolerance, "
                "source, explained)");
  EXPECT_EQ(error_of("targets:\n  - {name: a, metric: x, paper: 1, explained: 'See #3'}\n"),
            file + ":2: explained: expected an anchor of docs/MODEL.md (a-z, 0-9, '-')");
  EXPECT_EQ(error_of("targets:\n  - {name: a, paper: 1}\n"),
            file + ":2: metric: missing (expected a dotted metric path)");
  EXPECT_EQ(error_of("tolerance: 2\ntargets: []\n"),
            file + ":1: tolerance: expected a relative tolerance in (0, 1), got '2'");
  EXPECT_NE(error_of("targets: [\n").find(file + ":"), std::string::npos);
  EXPECT_EQ(error_of("target:\n  - {name: a, metric: x, paper: 1}\n"),
            file +
                ":1: target: unknown key (expected 'targets', 'tolerance', 'baselines' or "
                "'characterization')");
}

TEST(PaperCheck, TheComparedBaselinesLoadAndTheirErrorsNameTheLine) {
  TempDir dir;
  const auto error_of = [&](const std::string& text) {
    try {
      load_baselines(write_targets(dir.path(), text));
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string file = (dir.path() / "targets.yaml").string();
  const std::vector<ComparedBaseline> shipped = load_baselines(default_targets_path());
  ASSERT_GE(shipped.size(), 2u);
  EXPECT_EQ(shipped[1].name, "single_core");
  EXPECT_EQ(baseline_platform(shipped[1]), "car_single_core");
  EXPECT_EQ(baseline_platform(shipped[0]), "edx_car");
  EXPECT_TRUE(load_baselines(write_targets(dir.path(), "targets: []\n")).empty());
  EXPECT_EQ(error_of("baselines:\n  - {name: a, config: c.yaml, colour: red}\n"),
            file + ":2: baselines[].colour: unknown key (expected name, config, description)");
  EXPECT_EQ(error_of("baselines:\n  - {name: A-1, config: c.yaml}\n"),
            file + ":2: baselines[].name: expected a metric key (a-z, 0-9, '_')");
  EXPECT_EQ(error_of("baselines:\n  - {name: a}\n"),
            file + ":2: baselines[].config: missing (expected a platform file)");
  EXPECT_EQ(error_of("baselines:\n  - {name: a, config: x}\n  - {name: a, config: y}\n"),
            file + ":3: baselines[].name: duplicate baseline 'a'");
  EXPECT_EQ(error_of("baselines: 3\n"), file + ":1: baselines: expected a list of baselines");
}

TEST(Report, WritesIndexAndPlots) {
  TempDir dir;
  arch::write_results(dir.path() / "r.db", arch::result_rows(hand_made()));
  const ResultsData data = read_results(dir.path() / "r.db");
  ReportOptions options;
  options.out_dir = dir.path() / "report";
  const ReportResult result = write_report(data, options);
  const std::string html = edx::testing::read_file(dir.path() / "report" / "index.html");
  EXPECT_NE(html.find("Latency statistics"), std::string::npos);
  EXPECT_NE(html.find("Backend kernel breakdown"), std::string::npos);
  EXPECT_NE(html.find("kalman_gain"), std::string::npos);
  EXPECT_NE(html.find("2.00×"), std::string::npos);  // e2e speedup 100 / 50
  // The summary comes first, the run is named platform × trace; no paper check (not Edx-Car).
  EXPECT_LT(html.find("id=\"summary\""), html.find("<h2>Runs</h2>"));
  EXPECT_NE(html.find("hand_made × "), std::string::npos);
  EXPECT_EQ(html.find("Paper check"), std::string::npos);
  // Nothing left beside the report (no staging directory).
  EXPECT_EQ(edx::testing::entries(dir.path()).size(), 2u);  // r.db and report
  // No timeline was stored: the page says how to keep one.
  EXPECT_NE(html.find("No whole-system timeline stored"), std::string::npos);
  if (!gnuplot_available()) GTEST_SKIP() << "gnuplot not installed: plots not checked";
  ASSERT_TRUE(result.plotted);
  // CDF, per-frame (vio, slam), backend breakdown, FPS, energy.
  EXPECT_EQ(result.images.size(), 6u);
  for (const std::string& image : result.images) {
    const std::string svg = edx::testing::read_file(dir.path() / "report" / image);
    ASSERT_GT(svg.size(), 1000u) << image;
    EXPECT_NE(svg.find("<svg"), std::string::npos) << image;
    EXPECT_NE(svg.find("</svg>"), std::string::npos) << image;
    EXPECT_NE(html.find("src=\"" + image + "\""), std::string::npos) << image;
  }
}

/// hand_made() as a run of `platform` with its design on `device` (LUT 137 040: half a ZU9),
/// on the trace `trace_path` (hash `trace_hash`), its frames' modes cycling through `modes`.
arch::SystemResult platform_run(const std::string& platform, const std::string& device,
                                const std::string& trace_path, const std::string& trace_hash,
                                const std::vector<std::string>& modes) {
  arch::SystemResult r = hand_made();
  r.platform = platform;
  r.config_hash = platform == "edx_car" ? "00000000000000ca" : "00000000000000d0";
  r.trace_path = trace_path;
  r.trace_hash = trace_hash;
  r.resources.device = arch::Device::by_name(device);
  r.resources.total.shared = {137040, 100000, 1260, 456};
  r.resources.total.ns = {274080, 200000, 2520, 912};
  for (arch::VariantResult* v : {&r.baseline, &r.accelerated}) {
    for (std::size_t i = 0; i < v->frames.size(); ++i) v->frames[i].mode = modes[i % modes.size()];
    const arch::ModeSummary all = v->modes.at("all");
    v->modes.clear();
    v->modes["all"] = all;
    for (const std::string& m : modes) v->modes[m] = all;
  }
  return r;
}

TEST(Report, PaperChecksOfEdxCarRunsOnlyThePaperMixFirst) {
  TempDir dir;
  // The paper mix's trace: its meta sequence is what `edx trace --mix paper` writes.
  const std::filesystem::path mix = dir.path() / "c_paper.db";
  {
    trace::TraceMeta meta;
    for (const std::string_view key : trace::kRequiredMetaKeys) meta[std::string(key)] = "test";
    meta["sequence"] = "mix:paper";
    meta["precision"] = "fp64";
    trace::TraceWriter writer(mix, meta);
    writer.finish();
  }
  const std::filesystem::path db = dir.path() / "r.db";
  // In database (run id) order: a SLAM-only run, a VIO + SLAM run, the paper mix (here with SLAM
  // frames only, so that only its trace puts it first), a drone run.
  arch::write_results(db, arch::result_rows(platform_run("edx_car", "xc7v690t", "a_slam.db",
                                                         "0000000000000001", {"slam"})));
  arch::write_results(db, arch::result_rows(platform_run("edx_car", "xc7v690t", "b_two.db",
                                                         "0000000000000002", {"vio", "slam"})));
  arch::write_results(db, arch::result_rows(platform_run("edx_car", "xc7v690t", mix.string(),
                                                         "0000000000000003", {"slam"})));
  arch::write_results(db, arch::result_rows(platform_run("edx_drone", "zu9cg", "drone.db",
                                                         "0000000000000004", {"vio", "slam"})));
  const ResultsData data = read_results(db);
  ASSERT_EQ(data.runs.size(), 4u);
  EXPECT_TRUE(is_edx_car_run(data.runs[0]));
  EXPECT_FALSE(is_edx_car_run(data.runs[3]));
  ReportOptions options;
  options.out_dir = dir.path() / "report";
  options.gnuplot = "/nonexistent/gnuplot";
  write_report(data, options);
  const std::string html = edx::testing::read_file(dir.path() / "report" / "index.html");
  const std::size_t paper_mix = html.find("Paper check: edx_car × c_paper.db");
  const std::size_t two_modes = html.find("Paper check: edx_car × b_two.db");
  const std::size_t slam = html.find("Paper check: edx_car × a_slam.db");
  ASSERT_NE(slam, std::string::npos);
  EXPECT_LT(paper_mix, two_modes);
  EXPECT_LT(two_modes, slam);
  EXPECT_EQ(html.find("Paper check: edx_drone"), std::string::npos);
  // The SLAM-only run's registration and VIO figures are n/a, not misses.
  EXPECT_NE(html.find("<span title=\"no registration frames here\">n/a</span>"), std::string::npos);
  EXPECT_NE(html.find("<span title=\"no vio frames here\">n/a</span>"), std::string::npos);
  // Resources: each run against its own device; Table III for the three Edx-Car runs only.
  EXPECT_NE(html.find("The design against its own device, ZU9CG"), std::string::npos);
  EXPECT_NE(html.find("<td>LUT</td><td>137040</td><td>274080</td><td>274080</td><td>50.0%</td>"
                      "<td>100.0%</td>"),
            std::string::npos);
  EXPECT_NE(html.find("<td>LUT</td><td>137040</td><td>274080</td><td>433200</td><td>31.6%</td>"),
            std::string::npos);
  std::size_t table_iii = 0;
  for (std::size_t at = html.find("Table III figure (Edx-Car)"); at != std::string::npos;
       at = html.find("Table III figure (Edx-Car)", at + 1)) {
    ++table_iii;
  }
  EXPECT_EQ(table_iii, 3u);
  EXPECT_NE(html.find("is compared only for Edx-Car runs"), std::string::npos);
}

TEST(PaperCheck, AnEdxCarRunIsTheEdxCarPlatformOnTableIIIsDevice) {
  TempDir dir;
  const std::filesystem::path db = dir.path() / "r.db";
  arch::write_results(db, arch::result_rows(platform_run("edx_car", "zu9eg", "t.db",
                                                         "0000000000000001", {"slam"})));
  arch::write_results(db, arch::result_rows(platform_run("car_single_core", "xc7v690t", "t.db",
                                                         "0000000000000002", {"slam"})));
  const ResultsData data = read_results(db);
  ASSERT_EQ(data.runs.size(), 2u);
  for (const RunData& r : data.runs) EXPECT_FALSE(is_edx_car_run(r)) << r.platform;
}

TEST(Report, AWorkloadSweepGetsItsFrameRateAndEnergyPerWorkloadPoint) {
  TempDir dir;
  const std::filesystem::path db = dir.path() / "r.db";
  const arch::SystemResult run = hand_made();
  arch::write_results(db, arch::result_rows(run));
  {
    // Two points of a workload sweep: one simulated on its trace, one whose trace failed.
    SQLite::Database d(db.string(), SQLite::OPEN_READWRITE);
    arch::create_results_tables(d, results::TableGroup::kSweep);
    d.exec(
        "INSERT INTO sweeps VALUES ('study', 'study.yaml', 'car.yaml', 'study.traces', 2, "
        "'{\"objectives\": [{\"maximize\": \"fps\"}], \"workload\": {\"mix\": \"paper\"}}')");
    SQLite::Statement put(d,
                          "INSERT INTO sweep_points (sweep_id, point, run_id, parameters_json, "
                          "metrics_json, feasible, pareto, workload, error) VALUES ('study', ?, ?, "
                          "?, ?, ?, ?, ?, ?)");
    put.bind(1, 0);
    put.bind(2, arch::run_id_of(run.config_hash, run.trace_hash));
    put.bind(3, R"({"workload.features": "500"})");
    put.bind(4, R"({"fps": 20.0})");
    put.bind(5, 1);
    put.bind(6, 1);
    put.bind(7, "aaaa");
    put.bind(8);
    put.exec();
    put.reset();
    put.bind(1, 1);
    put.bind(2, "");
    put.bind(3, R"({"workload.features": "0"})");
    put.bind(4, "{}");
    put.bind(5, 0);
    put.bind(6, 0);
    put.bind(7, "bbbb");
    put.bind(8, "features 0 cannot be traced");
    put.exec();
  }
  const ResultsData data = read_results(db);
  ASSERT_EQ(data.sweeps.size(), 1u);
  EXPECT_TRUE(data.sweeps[0].traces_workload);
  EXPECT_EQ(data.sweeps[0].points[1].error, "features 0 cannot be traced");
  EXPECT_EQ(data.sweeps[0].points[0].workload, "aaaa");
  ReportOptions options;
  options.out_dir = dir.path() / "report";
  write_report(data, options);
  const std::string html = edx::testing::read_file(dir.path() / "report" / "index.html");
  EXPECT_NE(html.find("Per workload point"), std::string::npos);
  EXPECT_NE(html.find("failed: features 0 cannot be traced"), std::string::npos);
  if (!gnuplot_available()) GTEST_SKIP() << "gnuplot not installed: plots not checked";
  const std::string svg = edx::testing::read_file(dir.path() / "report" / "sweep1_workloads.svg");
  EXPECT_NE(svg.find("<svg"), std::string::npos);
  EXPECT_NE(html.find("src=\"sweep1_workloads.svg\""), std::string::npos);
  // One bar group: the traced point, labelled by its workload value.
  EXPECT_NE(svg.find("features=500"), std::string::npos);
  EXPECT_EQ(svg.find("features=0"), std::string::npos);
}

TEST(Report, StoredTimelineIsWrittenBesideTheReportAndLinked) {
  TempDir dir;
  arch::SystemResult run = hand_made();
  run.timeline_json = R"({"traceEvents":[{"name":"f2","ph":"X","ts":0,"dur":5}]})";
  run.timeline_first = 2;
  run.timeline_frames = 3;
  arch::write_results(dir.path() / "r.db", arch::result_rows(run));
  const ResultsData data = read_results(dir.path() / "r.db");
  ASSERT_EQ(data.runs.size(), 1u);
  ASSERT_EQ(data.runs[0].timelines.size(), 1u);
  EXPECT_EQ(data.runs[0].timelines[0].json, run.timeline_json);
  EXPECT_EQ(data.runs[0].timelines[0].first_frame, 2);
  EXPECT_EQ(data.runs[0].timelines[0].frames, 3);
  ReportOptions options;
  options.out_dir = dir.path() / "report";
  options.gnuplot = "/nonexistent/gnuplot";
  write_report(data, options);
  const std::string html = edx::testing::read_file(dir.path() / "report" / "index.html");
  EXPECT_NE(html.find("frames 2–4: <a href=\"run1_timeline.json\">"), std::string::npos);
  EXPECT_EQ(edx::testing::read_file(dir.path() / "report" / "run1_timeline.json"),
            run.timeline_json);
  // Writing the run again without a timeline removes the stored one.
  arch::write_results(dir.path() / "r.db", arch::result_rows(hand_made()));
  EXPECT_TRUE(read_results(dir.path() / "r.db").runs[0].timelines.empty());
}

TEST(Report, NewerResultsSchemaIsRefusedNamingTheFile) {
  TempDir dir;
  const std::filesystem::path db = dir.path() / "r.db";
  arch::write_results(db, arch::result_rows(hand_made()));
  {
    SQLite::Database raw(db.string(), SQLite::OPEN_READWRITE);
    raw.exec(fmt::format("PRAGMA user_version = {}", results::kSchemaVersion + 1));
  }
  try {
    read_results(db);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()),
              fmt::format("{}: results schema version {} is newer than this edx reads ({}); use "
                          "a newer edx",
                          db.string(), results::kSchemaVersion + 1, results::kSchemaVersion));
  }
  try {
    arch::write_results(db, arch::result_rows(hand_made()));
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("is newer than this edx reads"), std::string::npos)
        << e.what();
  }
}

TEST(Report, BadDatabaseIsOneLineError) {
  TempDir dir;
  std::ofstream(dir.path() / "text.db") << "not a database at all, just some text\n";
  EXPECT_THROW(
      {
        try {
          read_results(dir.path() / "text.db");
        } catch (const std::runtime_error& e) {
          const std::string what = e.what();
          EXPECT_EQ(what.find('\n'), std::string::npos);
          EXPECT_EQ(what.rfind((dir.path() / "text.db").string(), 0), 0u) << what;
          throw;
        }
      },
      std::runtime_error);
  {
    SQLite::Database empty((dir.path() / "empty.db").string(),
                           SQLite::OPEN_READWRITE | SQLite::OPEN_CREATE);
    empty.exec("CREATE TABLE other (x INTEGER)");
  }
  try {
    read_results(dir.path() / "empty.db");
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("no table 'runs'"), std::string::npos) << e.what();
  }
  // The command: one line on stderr, exit 1, no report directory.
  auto bad = edx::testing::run_command(edx::testing::built_binary("edx") + " report " +
                                       (dir.path() / "text.db").string() + " --out " +
                                       (dir.path() / "out").string());
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_EQ(std::count(bad.err.begin(), bad.err.end(), '\n'), 1) << bad.err;
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "out"));
}

}  // namespace
}  // namespace edx::reports
