// Sweeps over workload parameters (arch/sweep/workload.hpp): the spec's workload section, one
// trace per workload point in a content-addressed store, reuse across runs and sweeps, a failed
// workload point recorded without stopping the sweep, and the rows a remote worker sends.
#include <SQLiteCpp/SQLiteCpp.h>
#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <fstream>
#include <mutex>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "arch/results/results_db.hpp"
#include "arch/sweep/sweep.hpp"
#include "arch/sweep/sweep_engine.hpp"
#include "arch/sweep/workload.hpp"
#include "tests/arch/sweep/sweep_fixture.hpp"
#include "tests/support/temp_dir.hpp"
#include "workloads/trace/reader.hpp"

namespace edx::arch {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

/// A stand-in for the pipeline: workload {features: N} traces the fixture's four frames with
/// projection kernels of N points more each (so each workload point simulates differently);
/// features 13 fails as a bad workload would.
struct FakeTracer {
  std::atomic<int> traced{0};
  WorkloadTracer tracer(const std::string& version = "v1") {
    return {[](const nlohmann::json& w) {
              nlohmann::json resolved = {{"features", 100}};
              for (const auto& [key, value] : w.items()) {
                if (key != "features") throw InputError({}, key, "unknown parameter");
                const int n = std::stoi(value.get<std::string>());
                if (n < 1) throw InputError::expected("features", "at least 1", std::to_string(n));
                resolved["features"] = n;
              }
              return resolved;
            },
            [this](const nlohmann::json& resolved, const std::filesystem::path& out,
                   const std::filesystem::path& data_dir) {
              EXPECT_EQ(data_dir.filename(), "data");
              const int features = resolved.at("features").get<int>();
              if (features == 13) throw std::runtime_error("features 13 cannot be traced");
              ++traced;
              trace::TraceMeta meta = sweep_trace_meta();
              meta["pipeline_params"] = resolved.dump();
              trace::TraceWriter writer(out, meta);
              for (int i = 0; i < 4; ++i) writer.append(sweep_frame(i, 1000 * features + 500 * i));
              writer.finish();
            },
            version};
  }
};

struct WorkloadSweep : ::testing::Test {
  edx::testing::TempDir dir;
  FakeTracer fake;
  void SetUp() override {
    std::ofstream(dir.path() / "base.yaml")
        << "name: w\nbackend: {clock_mhz: 100, spm_bytes: 67108864, units: {gemm: {block: 2}}}\n"
           "scheduler: {policy: always, training_fraction: 0}\n";
  }
  SweepSpec spec(const std::string& features, const std::string& extra = {}) const {
    return SweepSpec::parse(
        "base: base.yaml\nworkload: {features: 2}\nparameters:\n"
        "  backend.units.gemm.block: {values: [1, 4]}\n"
        "  workload.features: {values: [" +
            features + "]}\n" + extra + "objectives: [{minimize: e2e_latency_mean}]\n",
        "w.yaml", dir.path());
  }
  SweepOptions options(const std::string& db, const std::string& version = "v1") {
    SweepOptions o;
    o.db = dir.path() / db;
    o.jobs = 2;
    o.tracer = fake.tracer(version);
    return o;
  }
};

// A workload's precision is its design's: each point's platform computes at its workload's
// precision, and backend.precision is then no parameter of its own.
TEST_F(WorkloadSweep, BackendPrecisionFollowsTheWorkloadsPrecision) {
  const SweepSpec s = SweepSpec::parse(
      "base: base.yaml\nworkload: {features: 2}\nparameters:\n"
      "  workload.precision: {values: [fp64, fp32]}\n"
      "  backend.units.gemm.block: {values: [1, 4]}\nobjectives: [{minimize: dsp}]\n",
      "w.yaml", dir.path());
  const SweepPoints points(s);
  ASSERT_EQ(points.size(), 4u);
  EXPECT_EQ(sweep_platform(s, points.at(0)).backend->precision(), trace::Precision::kFp64);
  EXPECT_EQ(sweep_platform(s, points.at(3)).backend->precision(), trace::Precision::kFp32);
  const SweepSpec fixed = SweepSpec::parse(
      "base: base.yaml\nworkload: {features: 2, precision: fp32}\nparameters:\n"
      "  backend.units.gemm.block: {values: [1, 4]}\nobjectives: [{minimize: dsp}]\n",
      "w.yaml", dir.path());
  EXPECT_EQ(sweep_platform(fixed, SweepPoints(fixed).at(1)).backend->precision(),
            trace::Precision::kFp32);
  // Without a workload precision the platform's own stands (the trace's is checked when run).
  EXPECT_EQ(sweep_platform(spec("1"), SweepPoints(spec("1")).at(0)).backend->precision(),
            trace::Precision::kFp64);
  try {
    SweepSpec::parse(
        "base: base.yaml\nworkload: {features: 2}\nparameters:\n"
        "  workload.precision: {values: [fp64, fp32]}\n"
        "  backend.precision: {values: [fp64, fp32]}\nobjectives: [{minimize: dsp}]\n",
        "w.yaml", dir.path());
    ADD_FAILURE() << "no error";
  } catch (const std::exception& e) {
    EXPECT_STREQ(e.what(),
                 "w.yaml:5: parameters.backend.precision: follows workload.precision (one "
                 "precision per design: the units compute at the trace's); sweep "
                 "workload.precision instead");
  }
}

TEST_F(WorkloadSweep, WorkloadParametersComeFirstAndNeedTheSection) {
  const SweepSpec s = spec("1, 3");
  ASSERT_EQ(s.parameters.size(), 2u);
  EXPECT_EQ(s.parameters[0].key, "workload.features");  // written second, enumerated first
  EXPECT_EQ(s.workload_parameters, 1u);
  const SweepPoints points(s);
  ASSERT_EQ(points.size(), 4u);
  EXPECT_EQ(points.at(0).workload(s), (nlohmann::json{{"features", "1"}}));
  EXPECT_EQ(points.at(1).workload_index(s), 0u);  // the gemm block varies fastest
  EXPECT_EQ(points.at(2).workload_index(s), 1u);
  EXPECT_EQ(points.at(3).workload(s), (nlohmann::json{{"features", "3"}}));

  const auto error = [&](const std::string& text) {
    try {
      SweepSpec::parse(text, "w.yaml", dir.path());
    } catch (const std::exception& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(error("base: base.yaml\nparameters:\n  workload.features: {values: [1]}\n"
                  "objectives: [{minimize: dsp}]\n"),
            "w.yaml:3: parameters.workload.features: a workload parameter needs a workload: "
            "section (the sweep then traces each workload point)");
  EXPECT_THAT(error("base: base.yaml\ntrace: t.db\nworkload: {features: 1}\nparameters:\n"
                    "  backend.units.gemm.block: {values: [1]}\nobjectives: [{minimize: dsp}]\n"),
              HasSubstr("w.yaml:3: workload: give a trace or a workload, not both"));
  // A search varies workload parameters too (their points traced as it asks for them).
  EXPECT_EQ(
      error("base: base.yaml\nworkload: {features: 1}\nparameters:\n"
            "  workload.features: {values: [1, 2]}\n  backend.units.gemm.block: {values: [1]}\n"
            "sampling: {nsga2: {generations: 1, population: 8}}\n"
            "objectives: [{minimize: dsp}]\n"),
      "no error");
  EXPECT_EQ(error("base: base.yaml\nworkload: {}\nparameters:\n"
                  "  workload.seed: {range: {from: 1, to: 200, step: 1}}\n"
                  "  workload.features: {range: {from: 1, to: 100, step: 1}}\n"
                  "sampling: {random: {samples: 3}}\nobjectives: [{minimize: dsp}]\n"),
            "w.yaml:4: parameters: the workload.* parameters make 2e+04 workload points (at most "
            "10^4: each is a trace of the real pipeline)");
}

TEST_F(WorkloadSweep, EachWorkloadPointIsTracedOnceIntoTheStoreAndReused) {
  const SweepSpec s = spec("1, 3");
  const SweepOutcome first = run_sweep(s, options("r.db"));
  EXPECT_EQ(fake.traced, 2);
  EXPECT_EQ(first.traced, 2u);
  EXPECT_EQ(first.computed, 4u);
  ASSERT_EQ(first.points.size(), 4u);
  // Two workload points, two traces: the points on one trace share its hash, and the larger
  // kernels of features 3 take longer.
  EXPECT_EQ(first.points[0].workload, first.points[1].workload);
  EXPECT_NE(first.points[0].workload, first.points[2].workload);
  EXPECT_LT(first.points[0].objectives[0], first.points[2].objectives[0]);
  const std::filesystem::path store = dir.path() / "r.traces";
  EXPECT_TRUE(std::filesystem::exists(store / (first.points[0].workload + ".db")));
  EXPECT_TRUE(std::filesystem::exists(store / (first.points[2].workload + ".db")));
  EXPECT_EQ(workload_hash({{"features", 1}}, "v1"), first.points[0].workload);

  SQLite::Database db((dir.path() / "r.db").string());
  EXPECT_EQ(db.execAndGet("SELECT COUNT(*) FROM sweep_workloads WHERE error IS NULL").getInt(), 2);
  // The run of each point used its workload's trace.
  SQLite::Statement q(db,
                      "SELECT COUNT(*) FROM sweep_points p JOIN sweep_workloads w ON "
                      "p.workload = w.workload JOIN runs r ON r.run_id = p.run_id WHERE "
                      "r.trace_hash = w.trace_hash");
  ASSERT_TRUE(q.executeStep());
  EXPECT_EQ(q.getColumn(0).getInt(), 4);

  // Resumed: nothing traced or simulated again.
  const SweepOutcome again = run_sweep(s, options("r.db"));
  EXPECT_EQ(fake.traced, 2);
  EXPECT_EQ(again.computed, 0u);
  EXPECT_EQ(again.skipped, 4u);
  // Another sweep on the same store reuses the traces of the same workload points; a new code
  // version traces again.
  SweepOptions other = options("other.db");
  other.trace_store = store;
  EXPECT_EQ(run_sweep(spec("3, 5"), other).traced, 1u);
  EXPECT_EQ(fake.traced, 3);
  SweepOptions newer = options("newer.db", "v2");
  newer.trace_store = store;
  EXPECT_EQ(run_sweep(s, newer).traced, 2u);
  EXPECT_EQ(fake.traced, 5);
}

TEST_F(WorkloadSweep, AFailedWorkloadPointIsRecordedAndTheSweepGoesOn) {
  const SweepOutcome out = run_sweep(spec("1, 13"), options("r.db"));
  EXPECT_TRUE(out.complete);
  EXPECT_EQ(out.failed, 2u);
  EXPECT_EQ(out.computed, 2u);
  ASSERT_EQ(out.points.size(), 4u);
  EXPECT_EQ(out.points[2].error, "features 13 cannot be traced");
  EXPECT_FALSE(out.points[2].feasible);
  EXPECT_EQ(out.points[2].run_id, "");
  ASSERT_FALSE(out.front.empty());
  for (std::size_t i : out.front) EXPECT_LT(out.points[i].index, 2u);  // traced points only
  SQLite::Database db((dir.path() / "r.db").string());
  EXPECT_EQ(db.execAndGet("SELECT COUNT(*) FROM sweep_points WHERE error = 'features 13 cannot "
                          "be traced'")
                .getInt(),
            2);
  EXPECT_EQ(db.execAndGet("SELECT error FROM sweep_workloads WHERE error IS NOT NULL").getString(),
            "features 13 cannot be traced");
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "r.traces" /
                                       (workload_hash({{"features", 13}}, "v1") + ".db")));
  // The export names each point's workload point and error.
  EXPECT_EQ(export_csv(dir.path() / "r.db", "", "w", dir.path() / "p.csv"), 4u);
  std::ifstream csv(dir.path() / "p.csv");
  std::string header, first, failed;
  std::getline(csv, header);
  std::getline(csv, first);
  std::getline(csv, failed);
  std::getline(csv, failed);
  EXPECT_EQ(
      header,
      "point,run_id,backend.units.gemm.block,workload.features,e2e_latency_mean,feasible,pareto,"
      "workload,error");
  EXPECT_THAT(failed, ::testing::EndsWith(",0,0," + out.points[2].workload +
                                          ",features 13 cannot be traced"));
}

TEST_F(WorkloadSweep, BadWorkloadValuesFailBeforeAnyWork) {
  try {
    run_sweep(spec("1, 0"), options("r.db"));
    FAIL() << "expected an error";
  } catch (const std::exception& e) {
    // At the line of the value, keyed as the spec writes it.
    EXPECT_STREQ(e.what(), "w.yaml:5: workload.features: expected at least 1, got '0'");
  }
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "r.db"));
  SweepOptions no_tracer = options("r.db");
  no_tracer.tracer = {};
  EXPECT_THROW(run_sweep(spec("1"), no_tracer), std::runtime_error);
  EXPECT_EQ(fake.traced, 0);
}

TEST(WorkloadSweepSpec, TheResolutionFeaturesStudyIsFourWorkloadPointsOnEdxCar) {
  const SweepSpec s = SweepSpec::load(std::filesystem::path(EDX_SOURCE_DIR) / "sweeps" /
                                      "resolution_features.yaml");
  EXPECT_TRUE(s.traces_workload());
  EXPECT_EQ(s.workload_parameters, 2u);
  EXPECT_EQ(s.parameters.size(), 2u);  // no platform parameter: the base, Edx-Car
  EXPECT_EQ(grid_size(s), 4.0);
  EXPECT_EQ(s.workload, (nlohmann::json{{"mix", "paper"}, {"frames", "400"}, {"seed", "1"}}));
  EXPECT_EQ(s.base.filename(), "edx_car.yaml");
  const SweepPoints points(s);
  EXPECT_EQ(points.at(3).workload(s)["resolution"], "1280x720");
  EXPECT_EQ(points.at(3).workload(s)["features"], "1000");
}

TEST(WorkloadStore, HashCoversParametersAndVersion) {
  const nlohmann::json a = {{"features", 500}, {"resolution", "640x480"}};
  EXPECT_EQ(workload_hash(a, "r1"), workload_hash(a, "r1"));
  EXPECT_NE(workload_hash(a, "r1"), workload_hash(a, "r2"));
  EXPECT_NE(workload_hash(a, "r1"),
            workload_hash({{"features", 1000}, {"resolution", "640x480"}}, "r1"));
  EXPECT_EQ(workload_hash(a, "r1").size(), 16u);
  EXPECT_EQ(default_trace_store("/x/results.db"), "/x/results.traces");
  EXPECT_EQ(default_trace_store("out"), "out.traces");
}

TEST(WorkloadStore, OpeningSweepsTmpOfWritersThatAreGoneAndRefusesWhatCannotBeAStore) {
  testing::TempDir dir;
  const fs::path store = dir.path() / "store";
  EXPECT_EQ(sweep_engine::open_trace_store(store), 0u);  // created, with its tmp/
  ASSERT_TRUE(fs::is_directory(store / "tmp"));
  // A child that exits at once: its pid is then of no running process (reaped below).
  const pid_t gone = ::fork();
  if (gone == 0) ::_exit(0);
  ASSERT_GT(gone, 0);
  ::waitpid(gone, nullptr, 0);
  const std::string host = sweep_engine::this_host();
  const auto tmp_file = [&](const std::string& name) {
    std::ofstream(store / "tmp" / name) << "partial";
    return store / "tmp" / name;
  };
  const fs::path dead = tmp_file(fmt::format("abc123-{}-{}-0.db", host, gone));
  const fs::path live = tmp_file(fmt::format("abc123-{}-{}-1.db", host, ::getppid()));
  const fs::path own = tmp_file(fmt::format("abc123-{}-{}-2.db", host, ::getpid()));
  const fs::path other_host = tmp_file(fmt::format("abc123-{}x-{}-3.db", host, gone));
  const fs::path not_a_trace = tmp_file("notes.txt");
  EXPECT_EQ(sweep_engine::open_trace_store(store), 1u);
  EXPECT_FALSE(fs::exists(dead));
  for (const fs::path& kept : {live, own, other_host, not_a_trace}) {
    EXPECT_TRUE(fs::exists(kept)) << kept;
  }
  // A file, and a folder under a file: one line naming the store.
  std::ofstream(dir.path() / "file") << "x";
  EXPECT_THAT([&] { sweep_engine::open_trace_store(dir.path() / "file"); },
              ::testing::ThrowsMessage<std::runtime_error>(::testing::HasSubstr(
                  (dir.path() / "file").string() + ": trace store: exists and is not a folder")));
  EXPECT_THAT([&] { sweep_engine::open_trace_store(dir.path() / "file" / "store"); },
              ::testing::ThrowsMessage<std::runtime_error>(::testing::HasSubstr(
                  (dir.path() / "file" / "store").string() + ": trace store: cannot create it")));
}

TEST(RunRows, ExportedRowsImportToTheSameTables) {
  edx::testing::TempDir dir;
  FakeTracer fake;
  std::ofstream(dir.path() / "base.yaml") << "name: w\n";
  const SweepSpec s = SweepSpec::parse(
      "base: base.yaml\nworkload: {}\nparameters:\n  workload.features: {values: [1]}\n"
      "objectives: [{minimize: e2e_latency_mean}]\n",
      "w.yaml", dir.path());
  SweepOptions o;
  o.db = dir.path() / "a.db";
  o.tracer = fake.tracer();
  o.per_frame = true;
  const SweepOutcome out = run_sweep(s, o);
  SQLite::Database a(o.db.string());
  const nlohmann::json rows = export_run_rows(a, out.points.at(0).run_id);
  EXPECT_EQ(rows["tables"]["runs"]["rows"].size(), 1u);
  EXPECT_EQ(rows["tables"]["frames"]["rows"].size(), 8u);  // 4 frames, baseline and accelerated
  SQLite::Database b(":memory:", SQLite::OPEN_READWRITE | SQLite::OPEN_CREATE);
  create_results_tables(b);
  import_run_rows(b, rows);
  import_run_rows(b, rows);  // replaces, never duplicates
  EXPECT_EQ(export_run_rows(b, out.points.at(0).run_id), rows);
  EXPECT_THROW(import_run_rows(b, nlohmann::json{{"tables", 1}}), std::runtime_error);
}

}  // namespace
}  // namespace edx::arch

namespace edx::arch {
namespace {

TEST(Seeds, ListsAndRangesInTheOrderGiven) {
  EXPECT_EQ(parse_seed_list("1-5"), (std::vector<std::uint64_t>{1, 2, 3, 4, 5}));
  EXPECT_EQ(parse_seed_list("7,3,1"), (std::vector<std::uint64_t>{7, 3, 1}));
  EXPECT_EQ(parse_seed_list("1-3,9"), (std::vector<std::uint64_t>{1, 2, 3, 9}));
  EXPECT_EQ(parse_seed_list("0"), (std::vector<std::uint64_t>{0}));
  for (const char* bad :
       {"", "1-", "-3", "5-1", "1,,2", "a", "1-3,2", "1.5", "0-1000", "99999999999999999999"}) {
    try {
      parse_seed_list(bad);
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), HasSubstr("--seeds")) << bad;
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
    }
  }
  EXPECT_EQ(parse_seed_list("0-999").size(), 1000u);
}

TEST(Seeds, AWorkloadFileIsAMapOfScalarsWithoutSeed) {
  edx::testing::TempDir dir;
  const std::filesystem::path file = dir.path() / "w.yaml";
  std::ofstream(file) << "mix: paper\nframes: 48\nresolution: 320x240\n";
  EXPECT_EQ(load_workload_file(file),
            (nlohmann::json{{"mix", "paper"}, {"frames", "48"}, {"resolution", "320x240"}}));
  std::ofstream(file) << "frames: 48\nseed: 3\n";
  EXPECT_THROW(
      {
        try {
          load_workload_file(file);
        } catch (const InputError& e) {
          EXPECT_THAT(e.what(), HasSubstr("w.yaml:2"));
          EXPECT_THAT(e.what(), HasSubstr("--seeds"));
          throw;
        }
      },
      InputError);
  std::ofstream(file) << "frames: [1, 2]\n";
  EXPECT_THROW(load_workload_file(file), InputError);
  EXPECT_THROW(load_workload_file(dir.path() / "missing.yaml"), std::runtime_error);
}

TEST(Seeds, EachSeedIsTracedOnceIntoTheStore) {
  // A tracer that writes the fixture's frames, longer kernels for larger seeds.
  edx::testing::TempDir dir;
  std::atomic<int> traced{0};
  const WorkloadTracer tracer{
      [](const nlohmann::json& w) {
        return nlohmann::json{{"seed", std::stoi(w.at("seed").get<std::string>())}};
      },
      [&traced](const nlohmann::json& resolved, const std::filesystem::path& out,
                const std::filesystem::path&) {
        ++traced;
        trace::TraceWriter writer(out, sweep_trace_meta());
        for (int i = 0; i < 4; ++i) {
          writer.append(sweep_frame(i, 1000 * resolved.at("seed").get<int>() + 500 * i));
        }
        writer.finish();
      },
      "v1"};
  const std::filesystem::path store = dir.path() / "store";
  const std::vector<SeedTrace> first =
      trace_seeds(tracer, nlohmann::json::object(), {1, 2, 3}, store);
  ASSERT_EQ(first.size(), 3u);
  EXPECT_EQ(traced, 3);
  EXPECT_EQ(first[1].seed, 2u);
  EXPECT_NE(first[0].trace, first[1].trace);
  for (const SeedTrace& s : first) EXPECT_TRUE(std::filesystem::is_regular_file(s.trace));
  EXPECT_EQ(first[0].trace, store / (workload_hash({{"seed", 1}}, "v1") + ".db"));
  // Again, and with one more seed: only the new one is traced.
  const std::vector<SeedTrace> again = trace_seeds(tracer, nlohmann::json::object(), {3, 4}, store);
  EXPECT_EQ(traced, 4);
  EXPECT_EQ(again[0].trace, first[2].trace);
}

/// The missing seeds traced at once (threads 2) give the traces of one thread: the same files
/// (hash names) with the same rows, in seed order; the "tracing" messages come first, in seed
/// order; the first failing seed's error is the one thrown.
TEST(Seeds, TwoThreadsTraceTheSeedsAtOnceIntoTheSameTraces) {
  edx::testing::TempDir dir;
  std::mutex mutex;
  std::condition_variable met;
  int active = 0, peak = 0;
  std::vector<std::string> events;
  const auto event = [&](std::string e) {
    const std::lock_guard lock(mutex);
    events.push_back(std::move(e));
  };
  // Seeds 5 and 6 fail; a tracer waits (up to 20 s) until two have been tracing at once.
  const WorkloadTracer tracer{
      [](const nlohmann::json& w) {
        return nlohmann::json{{"seed", std::stoi(w.at("seed").get<std::string>())}};
      },
      [&](const nlohmann::json& resolved, const fs::path& out, const fs::path&) {
        const int seed = resolved.at("seed").get<int>();
        event(fmt::format("trace {}", seed));
        {
          std::unique_lock lock(mutex);
          peak = std::max(peak, ++active);
          met.notify_all();
          met.wait_for(lock, std::chrono::seconds(20), [&] { return peak >= 2; });
          --active;
        }
        if (seed >= 5) throw std::runtime_error(fmt::format("seed {} broke", seed));
        trace::TraceWriter writer(out, sweep_trace_meta());
        for (int i = 0; i < 4; ++i) writer.append(sweep_frame(i, 1000 * seed + 500 * i));
        writer.finish();
      },
      "v1"};
  const auto message = [&](std::uint64_t seed) { event(fmt::format("tracing {}", seed)); };
  const std::vector<SeedTrace> two =
      trace_seeds(tracer, nlohmann::json::object(), {3, 1, 2}, dir.path() / "two", message, 2);
  EXPECT_EQ(peak, 2);  // two seeds traced at once
  ASSERT_GE(events.size(), 6u);
  EXPECT_EQ(std::vector(events.begin(), events.begin() + 3),
            (std::vector<std::string>{"tracing 3", "tracing 1", "tracing 2"}));
  peak = 2;  // one thread: no waiting for a second
  const std::vector<SeedTrace> one =
      trace_seeds(tracer, nlohmann::json::object(), {3, 1, 2}, dir.path() / "one", {}, 1);
  ASSERT_EQ(two.size(), 3u);
  ASSERT_EQ(one.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(two[i].seed, (std::vector<std::uint64_t>{3, 1, 2})[i]);
    EXPECT_EQ(one[i].seed, two[i].seed);
    const std::string file = workload_hash({{"seed", static_cast<int>(two[i].seed)}}, "v1") + ".db";
    EXPECT_EQ(two[i].trace, dir.path() / "two" / file);
    EXPECT_EQ(one[i].trace, dir.path() / "one" / file);
    EXPECT_EQ(trace::TraceReader(two[i].trace).read_all(),
              trace::TraceReader(one[i].trace).read_all());
  }
  // Seeds 5 and 6 fail at once: seed 5's error (the first in order) is thrown, seed 4 is stored.
  peak = 0;
  EXPECT_THAT(
      [&] {
        trace_seeds(tracer, nlohmann::json::object(), {4, 5, 6}, dir.path() / "two", {}, 2);
      },
      ::testing::ThrowsMessage<std::runtime_error>(
          HasSubstr(R"(workload {"seed":"5"}: seed 5 broke)")));
  EXPECT_TRUE(
      fs::is_regular_file(dir.path() / "two" / (workload_hash({{"seed", 4}}, "v1") + ".db")));
}

}  // namespace
}  // namespace edx::arch
