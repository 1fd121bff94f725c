// The bad-input suite (issue 21; docs/RELIABILITY.md): one case per failure a new user met, by
// class, each run through the real `edx` binary and held to the same three promises:
//   - the exit code (1 for a bad file or value, 2 for a bad command line),
//   - standard error is exactly one line, naming the file (with line and key where there is one),
//   - nothing in the case's folder is created, removed or changed (a FIFO stays a FIFO).
// Classes: 1 size checked first, 2 special files, 3 wrong kind of database, 4 nothing left by a
// failing command, 5 failed writes to stdout, 6 bad values, 7 errors that name the file, 8 one
// process per sweep, 9 trajectories that go back in time (repeated stamps are accepted: the
// last test).
#include <SQLiteCpp/SQLiteCpp.h>
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "tests/support/run_command.hpp"
#include "tests/support/temp_dir.hpp"

namespace edx::testing {
namespace {

namespace fs = std::filesystem;

const std::string kSource = EDX_SOURCE_DIR;
const std::string kGolden = kSource + "/tests/data/golden/golden_mix.db";
const std::string kCar = kSource + "/configs/edx_car.yaml";

/// Replaces every "{dir}", "{edx}", "{src}", "{golden}", "{car}" and "{host}" in `text`.
std::string expand(std::string text, const fs::path& dir) {
  char host[256] = {};
  ::gethostname(host, sizeof host - 1);
  const std::pair<std::string, std::string> names[] = {
      {"{dir}", dir.string()}, {"{edx}", built_binary("edx")},
      {"{src}", kSource},      {"{golden}", kGolden},
      {"{car}", kCar},         {"{host}", host}};
  for (const auto& [key, value] : names) {
    for (std::size_t at = text.find(key); at != std::string::npos;
         at = text.find(key, at + value.size())) {
      text.replace(at, key.size(), value);
    }
  }
  return text;
}

void write(const fs::path& dir, const std::string& name, const std::string& text) {
  std::ofstream(dir / name) << expand(text, dir);
}

/// A copy of the golden trace with `sql` applied.
void spoiled_trace(const fs::path& dir, const std::string& name, const std::string& sql) {
  fs::copy_file(kGolden, dir / name);
  SQLite::Database db((dir / name).string(), SQLite::OPEN_READWRITE);
  db.exec(sql);
}

/// A results database holding the golden trace's Edx-Car run.
void results_db(const fs::path& dir, const std::string& name) {
  const CommandResult r = run_command(
      expand(fmt::format("'{{edx}}' simulate --config '{{car}}' --trace '{{golden}}' --out "
                         "'{{dir}}/{}'",
                         name),
             dir));
  ASSERT_EQ(r.exit_code, 0) << r.err;
}

/// A sweep spec over the golden trace (or `trace`) with a valid grid.
std::string sweep_spec(const std::string& trace = "{golden}",
                       const std::string& objective = "dsp") {
  return "base: {car}\ntrace: " + trace +
         "\nparameters:\n  backend.units.gemm.block: {values: [2, 4]}\nobjectives: [{minimize: " +
         objective + "}]\n";
}

/// Nine levels of anchors, each a list of ten aliases of the one before: 10^9 nodes expanded.
std::string alias_bomb() {
  std::string text = "l0: &l0 [x, x, x, x, x, x, x, x, x, x]\n";
  for (int level = 1; level < 9; ++level) {
    text += fmt::format("l{}: &l{} [", level, level);
    for (int i = 0; i < 10; ++i) text += fmt::format("{}*l{}", i == 0 ? "" : ", ", level - 1);
    text += "]\n";
  }
  return text;
}

/// What is in a folder: each entry's type and, for regular files, their size and a hash of
/// their bytes.
std::map<std::string, std::string> snapshot(const fs::path& dir) {
  std::map<std::string, std::string> out;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    const std::string name = fs::relative(entry.path(), dir).string();
    if (entry.is_regular_file()) {
      const std::string bytes = read_text_file(entry.path());
      out[name] = fmt::format("file of {} bytes, hash {:016x}", bytes.size(),
                              std::hash<std::string>{}(bytes));
    } else {
      out[name] = entry.is_fifo() ? "fifo" : entry.is_directory() ? "dir" : "other";
    }
  }
  return out;
}

struct BadInputCase {
  std::string name;                            ///< c<class>_<what>
  std::function<void(const fs::path&)> setup;  ///< writes the case's files into its folder
  std::string command;                         ///< placeholders as expand()
  int exit_code = 1;
  std::string message;  ///< the whole of standard error, without its newline
};

std::vector<BadInputCase> cases() {
  const auto none = [](const fs::path&) {};
  return {
      // 1. Size before anything: a 10^9-point grid is refused at once, nothing created.
      {"c1_grid_of_a_billion_points",
       [](const fs::path& d) {
         write(d, "big.yaml",
               "base: {car}\ntrace: {golden}\nparameters:\n"
               "  backend.units.gemm.block: {range: {from: 1, to: 1000, step: 1}}\n"
               "  backend.clock_mhz: {range: {from: 1, to: 1000, step: 1}}\n"
               "  frontend.clock_mhz: {range: {from: 1, to: 1000, step: 1}}\n"
               "objectives: [{minimize: dsp}]\n");
       },
       "'{edx}' sweep '{dir}/big.yaml' --db '{dir}/r.db' --limit 2", 1,
       "edx: error: {dir}/big.yaml:4: parameters: the grid has 1e+09 points (more than 10^6); "
       "use random sampling or a search"},
      // ... and a YAML alias bomb (nine levels of ten aliases: 10^9 nodes in ten lines) in a
      // platform and in a sweep spec, at once, after at most 10^5 nodes walked.
      {"c1_platform_alias_bomb", [](const fs::path& d) { write(d, "bomb.yaml", alias_bomb()); },
       "'{edx}' simulate --config '{dir}/bomb.yaml' --trace '{golden}'", 1,
       "edx: error: {dir}/bomb.yaml:1: more than 100000 YAML nodes with its aliases expanded "
       "(nested anchors? edx reads documents of at most 100000 nodes)"},
      {"c1_sweep_spec_alias_bomb",
       [](const fs::path& d) { write(d, "s.yaml", sweep_spec() + alias_bomb()); },
       "'{edx}' sweep '{dir}/s.yaml' --db '{dir}/r.db'", 1,
       "edx: error: {dir}/s.yaml:6: more than 100000 YAML nodes with its aliases expanded "
       "(nested anchors? edx reads documents of at most 100000 nodes)"},
      // 2. Special files: a database output that is a FIFO is refused, not replaced.
      {"c2_results_database_onto_a_fifo",
       [](const fs::path& d) { ASSERT_EQ(::mkfifo((d / "ff").c_str(), 0600), 0); },
       "'{edx}' simulate --config '{car}' --trace '{golden}' --out '{dir}/ff'", 1,
       "edx: error: {dir}/ff: not a regular file (a results database is a file; give a file "
       "path)"},
      {"c2_report_folder_onto_a_file", [](const fs::path& d) { results_db(d, "good.db"); },
       "'{edx}' report '{dir}/good.db' --out '{dir}/good.db'", 1,
       "edx: error: {dir}/good.db: exists and is not a directory"},
      // 3. The wrong kind of database: a sweep never writes into a trace.
      {"c3_sweep_into_a_trace",
       [](const fs::path& d) {
         fs::copy_file(kGolden, d / "t.db");
         write(d, "s.yaml", sweep_spec());
       },
       "'{edx}' sweep '{dir}/s.yaml' --db '{dir}/t.db'", 1,
       "edx: error: {dir}/t.db: is an edx trace (schema version 4), not a results database"},
      {"c3_export_of_a_trace", [](const fs::path& d) { fs::copy_file(kGolden, d / "t.db"); },
       "'{edx}' export '{dir}/t.db' --table runs --out '{dir}/x.csv'", 1,
       "edx: error: {dir}/t.db: --table: no table 'runs' (tables: frames, kernels, meta, ops, "
       "tasks)"},
      // A results database of a version this edx does not write: refused by every reader.
      {"c3_report_of_a_corrupted_cell",
       [](const fs::path& d) {
         results_db(d, "r.db");
         SQLite::Database((d / "r.db").string(), SQLite::OPEN_READWRITE)
             .exec("UPDATE latency SET mean = 'fast' WHERE rowid = 1");
       },
       "'{edx}' report '{dir}/r.db' --out '{dir}/report'", 1,
       "edx: error: {dir}/r.db: table latency, column mean, row 1: expected a finite number, got "
       "text 'fast' (a corrupted results database)"},
      // Valid JSON of another shape in a run's summary: an error, not "not found" or zeros.
      {"c3_check_of_a_summary_of_another_shape",
       [](const fs::path& d) {
         results_db(d, "r.db");
         SQLite::Database((d / "r.db").string(), SQLite::OPEN_READWRITE)
             .exec("UPDATE runs SET summary_json = '{\"x\": 1}'");
       },
       "'{edx}' check --results '{dir}/r.db'", 1,
       "edx: error: {dir}/r.db: table runs, column summary_json, row 1: expected a JSON object "
       "holding the objects baseline, accelerated, comparison, resources, got no 'baseline' (a "
       "corrupted results database)"},
      {"c3_export_of_a_negative_schema_version",
       [](const fs::path& d) {
         results_db(d, "r.db");
         SQLite::Database((d / "r.db").string(), SQLite::OPEN_READWRITE)
             .exec("PRAGMA user_version = -3");
       },
       "'{edx}' export '{dir}/r.db' --table runs --out '{dir}/x.csv'", 1,
       "edx: error: {dir}/r.db: results schema version -3 (user_version) is not one edx writes "
       "(0 to 6)"},
      {"c3_export_of_a_newer_schema_version",
       [](const fs::path& d) {
         results_db(d, "r.db");
         SQLite::Database((d / "r.db").string(), SQLite::OPEN_READWRITE)
             .exec("PRAGMA user_version = 99");
       },
       "'{edx}' export '{dir}/r.db' --table runs --out '{dir}/x.csv'", 1,
       "edx: error: {dir}/r.db: results schema version 99 is newer than this edx reads (6); use a "
       "newer edx"},
      // 4. A failing command leaves nothing behind.
      {"c4_host_cost_fit_onto_its_own_trace",
       [](const fs::path& d) { fs::copy_file(kGolden, d / "t.db"); },
       "'{edx}' host-costs fit --trace '{dir}/t.db' --out '{dir}/t.db'", 1,
       "edx: error: {dir}/t.db: --out is a --trace of this fit; writing the table would "
       "overwrite its input (give another --out)"},
      {"c4_sweep_objective_names_no_metric",
       [](const fs::path& d) { write(d, "s.yaml", sweep_spec("{golden}", "happiness")); },
       "'{edx}' sweep '{dir}/s.yaml' --db '{dir}/r.db'", 1,
       "edx: error: {dir}/s.yaml:5: objectives[0]: unknown metric 'happiness' (docs/SWEEPS.md "
       "lists them)"},
      {"c4_sweep_over_a_trace_without_frames",
       [](const fs::path& d) {
         spoiled_trace(d, "empty.db",
                       "DELETE FROM ops; DELETE FROM kernels; DELETE FROM tasks; DELETE FROM "
                       "frames; UPDATE meta SET value = '0' WHERE key = 'frames'");
         write(d, "s.yaml", sweep_spec("{dir}/empty.db"));
       },
       "'{edx}' sweep '{dir}/s.yaml' --db '{dir}/r.db'", 1,
       "edx: error: {dir}/empty.db: the trace has no frames"},
      // 5. Output that cannot reach standard output fails the command.
      {"c5_stdout_on_a_full_device", none,
       "('{edx}' simulate --config '{car}' --trace '{golden}' >/dev/full)", 1,
       "edx: error: standard output: write failed (No space left on device)"},
      // 6. Values no run produces.
      {"c6_random_samples_beyond_a_million",
       [](const fs::path& d) {
         write(
             d, "s.yaml",
             "base: {car}\ntrace: {golden}\nparameters:\n  backend.units.gemm.block: {values: [2, "
             "4]}\nsampling: {random: {samples: 99999999999999999999}}\nobjectives: "
             "[{minimize: dsp}]\n");
       },
       "'{edx}' sweep '{dir}/s.yaml' --db '{dir}/r.db'", 1,
       "edx: error: {dir}/s.yaml:5: sampling.random.samples: expected an integer from 1 to 10^6, "
       "got '99999999999999999999'"},
      // Found by fuzz_sweep_spec (a seed beyond 2^64 was converted to an integer: undefined).
      {"c6_random_seed_beyond_two_to_the_53",
       [](const fs::path& d) {
         write(
             d, "s.yaml",
             "base: {car}\ntrace: {golden}\nparameters:\n  backend.units.gemm.block: {values: [2, "
             "4]}\nsampling: {random: {samples: 5, seed: 333333333333333333333337}}\nobjectives: "
             "[{minimize: dsp}]\n");
       },
       "'{edx}' sweep '{dir}/s.yaml' --db '{dir}/r.db'", 1,
       "edx: error: {dir}/s.yaml:5: sampling.random.seed: expected an integer from 0 to 2^53, got "
       "'333333333333333333333337'"},
      {"c6_range_of_unbounded_points",
       [](const fs::path& d) {
         write(d, "s.yaml",
               "base: {car}\ntrace: {golden}\nparameters:\n  backend.clock_mhz: {range: {from: 1, "
               "to: 1e300, step: 1e-300}}\nobjectives: [{minimize: dsp}]\n");
       },
       "'{edx}' sweep '{dir}/s.yaml' --db '{dir}/r.db'", 1,
       "edx: error: {dir}/s.yaml:4: parameters.backend.clock_mhz.range: more than 100000 values"},
      {"c6_platform_key_written_twice",
       [](const fs::path& d) {
         write(d, "p.yaml", "name: p\nbackend:\n  spm_bytes: 4\n  spm_bytes: 8\n");
       },
       "'{edx}' simulate --config '{dir}/p.yaml' --trace '{golden}' --out '{dir}/r.db'", 1,
       "edx: error: {dir}/p.yaml:4: backend.spm_bytes: written twice (also on line 3)"},
      {"c6_sweep_parameter_written_twice",
       [](const fs::path& d) {
         write(d, "s.yaml",
               "base: {car}\ntrace: {golden}\nparameters:\n  backend.units.gemm.block: {values: "
               "[2]}\n"
               "  backend.units.gemm.block: {values: [4]}\nobjectives: [{minimize: dsp}]\n");
       },
       "'{edx}' sweep '{dir}/s.yaml' --db '{dir}/r.db'", 1,
       "edx: error: {dir}/s.yaml:5: parameters.backend.units.gemm.block: written twice (also on "
       "line "
       "4)"},
      {"c6_number_beyond_a_double",
       [](const fs::path& d) { write(d, "p.yaml", "name: p\nbackend:\n  clock_mhz: 1e400\n"); },
       "'{edx}' simulate --config '{dir}/p.yaml' --trace '{golden}' --out '{dir}/r.db'", 1,
       "edx: error: {dir}/p.yaml:3: backend.clock_mhz: expected a number in [0.001, 1000], got "
       "'1e400'"},
      // A command-line range: its bound in a few digits (CLI11's own prints the largest double
      // in full, 309 digits).
      {"c6_option_below_its_range", none, "'{edx}' trace --mix paper --frames 0 --out '{dir}/t.db'",
       2, "edx: --frames: expected a number > 0, got '0' (see edx --help)"},
      // Issue 45: a value inside a key's old range that the model cannot take is refused at
      // the key; one the trace takes past its lines is placed at the key by the platform.
      {"c6_platform_clock_the_model_cannot_take",
       [](const fs::path& d) {
         write(d, "p.yaml", "extends: {car}\nname: p\nfrontend:\n  clock_mhz: 1e-300\n");
       },
       "'{edx}' simulate --config '{dir}/p.yaml' --trace '{golden}'", 1,
       "edx: error: {dir}/p.yaml:4: frontend.clock_mhz: expected a number in [0.001, 1000], got "
       "'1e-300'"},
      {"c6_platform_window_wider_than_the_traced_lines",
       [](const fs::path& d) {
         write(d, "p.yaml", "extends: {car}\nname: p\nfrontend:\n  fd_stencil: 255\n");
       },
       "'{edx}' simulate --config '{dir}/p.yaml' --trace '{golden}'", 1,
       "edx: error: {dir}/p.yaml:4: frontend.fd_stencil: a 255-pixel window is wider than the "
       "222-pixel lines of stencil buffer fe.L2 (a pyramid level of the trace's images)"},
      // ... and trace counts beyond what the images hold, or operands beyond any host's memory.
      {"c6_task_keypoints_beyond_its_images",
       [](const fs::path& d) {
         spoiled_trace(d, "t.db",
                       "UPDATE tasks SET keypoints = 1000000000000 WHERE frame_id = 0 AND seq = 6");
       },
       "'{edx}' simulate --config '{car}' --trace '{dir}/t.db'", 1,
       "edx: error: {dir}/t.db: frame 0, task 6 (FC): keypoints is 1000000000000, more than the "
       "4915200 pixels of a 64-level pyramid of the 320x240 images (meta.resolution)"},
      {"c6_op_operand_beyond_host_memory",
       [](const fs::path& d) {
         spoiled_trace(d, "t.db",
                       "UPDATE ops SET m = 1000000, n = 1000000 WHERE rowid = (SELECT MIN(rowid) "
                       "FROM ops)");
       },
       "'{edx}' simulate --config '{car}' --trace '{dir}/t.db'", 1,
       "edx: error: {dir}/t.db: frame 3, kernel 5 (normal_equations), op 0: an operand of m x n = "
       "1000000 x 1000000 elements, above the 2^32 no host holds"},
      {"c6_sweep_limit_of_zero", [](const fs::path& d) { write(d, "s.yaml", sweep_spec()); },
       "'{edx}' sweep '{dir}/s.yaml' --db '{dir}/r.db' --limit 0", 2,
       "edx: --limit: expected a number of points >= 1 (omit --limit for no limit) (see edx "
       "--help)"},
      {"c6_constraint_with_min_above_max",
       [](const fs::path& d) {
         write(d, "s.yaml", sweep_spec() + "constraints: [{metric: dsp, min: 5, max: 1}]\n");
       },
       "'{edx}' sweep '{dir}/s.yaml' --db '{dir}/r.db'", 1,
       "edx: error: {dir}/s.yaml:6: constraints[0].min: min 5 is above max 1: no value can meet "
       "it"},
      {"c6_empty_output_path", none,
       "'{edx}' simulate --config '{car}' --trace '{golden}' --out ''", 2,
       "edx: --out: expected a path, got '' (see edx --help)"},
      {"c6_negative_seed", none,
       "'{edx}' gen --scenario indoor_unknown --frames 2 --seed -1 --out '{dir}/g'", 2,
       "edx: --seed: expected a non-negative integer, got '-1' (see edx --help)"},
      {"c6_timeline_past_the_trace", none,
       "'{edx}' simulate --config '{car}' --trace '{golden}' --timeline '{dir}/t.json' "
       "--timeline-first 100000",
       1,
       "edx: error: {golden}: the timeline's first frame 100000 is past the trace's last (240 "
       "frames)"},
      {"c6_frame_count_that_disagrees_with_the_rows",
       [](const fs::path& d) {
         spoiled_trace(d, "t.db", "UPDATE meta SET value = '500' WHERE key = 'frames'");
       },
       "'{edx}' simulate --config '{car}' --trace '{dir}/t.db' --out '{dir}/r.db'", 1,
       "edx: error: {dir}/t.db: meta.frames says 500 but the trace has 240 frame rows"},
      {"c6_kernel_of_nine_exaseconds",
       [](const fs::path& d) {
         spoiled_trace(d, "t.db",
                       "UPDATE kernels SET host_ns = 9000000000000000000 WHERE rowid = (SELECT "
                       "min(rowid) FROM kernels)");
       },
       "'{edx}' simulate --config '{car}' --trace '{dir}/t.db' --out '{dir}/r.db'", 1,
       "edx: error: {dir}/t.db: frame 0, kernel 0 (preintegration): host_ns is "
       "9000000000000000000, above the plausible 10000000000000"},
      {"c6_task_of_two_billion_pixels",
       [](const fs::path& d) {
         spoiled_trace(d, "t.db", "UPDATE tasks SET pixels = 2000000000 WHERE rowid = 1");
       },
       "'{edx}' simulate --config '{car}' --trace '{dir}/t.db' --out '{dir}/r.db'", 1,
       "edx: error: {dir}/t.db: frame 0, task 0 (FD): per_level pixels sum to 192989, task says "
       "2000000000"},
      // 7. Errors name the file (and line, key or row).
      {"c7_trace_without_frames",
       [](const fs::path& d) {
         spoiled_trace(d, "t.db",
                       "DELETE FROM ops; DELETE FROM kernels; DELETE FROM tasks; DELETE FROM "
                       "frames; UPDATE meta SET value = '0' WHERE key = 'frames'");
       },
       "'{edx}' simulate --config '{car}' --trace '{dir}/t.db' --out '{dir}/r.db'", 1,
       "edx: error: {dir}/t.db: the trace has no frames"},
      {"c7_bad_meta_resolution",
       [](const fs::path& d) {
         spoiled_trace(d, "t.db", "UPDATE meta SET value = '320by240' WHERE key = 'resolution'");
       },
       "'{edx}' simulate --config '{car}' --trace '{dir}/t.db'", 1,
       "edx: error: {dir}/t.db: meta.resolution: expected WxH (e.g. 1280x720), got '320by240'"},
      {"c7_frame_without_frontend_rows",
       [](const fs::path& d) { spoiled_trace(d, "t.db", "DELETE FROM tasks WHERE frame_id = 0"); },
       "'{edx}' simulate --config '{car}' --trace '{dir}/t.db'", 1,
       "edx: error: {dir}/t.db: frame 0: no frontend task rows (the frontend model needs a "
       "frontend trace)"},
      {"c7_trace_of_another_schema_version",
       [](const fs::path& d) {
         SQLite::Database db((d / "t.db").string(), SQLite::OPEN_READWRITE | SQLite::OPEN_CREATE);
         db.exec(
             "CREATE TABLE meta (key TEXT, value TEXT); INSERT INTO meta VALUES "
             "('schema_version', '2'); CREATE TABLE frames (x); CREATE TABLE kernels (x)");
       },
       "'{edx}' simulate --config '{car}' --trace '{dir}/t.db'", 1,
       "edx: error: {dir}/t.db: trace schema version 2, this edx reads versions 3 to 5"},
      {"c7_text_file_as_a_results_database",
       [](const fs::path& d) { write(d, "junk.db", "hello\n"); },
       "'{edx}' export '{dir}/junk.db' --table runs --out '{dir}/x.csv'", 1,
       "edx: error: {dir}/junk.db: not a readable edx results database: file is not a "
       "database"},
      {"c7_text_file_as_a_sweep_database",
       [](const fs::path& d) {
         write(d, "junk.db", "hello\n");
         write(d, "s.yaml", sweep_spec());
       },
       "'{edx}' sweep '{dir}/s.yaml' --db '{dir}/junk.db'", 1,
       "edx: error: {dir}/junk.db: not a readable SQLite database: file is not a database"},
      {"c7_trajectory_that_is_a_folder", [](const fs::path& d) { fs::create_directory(d / "gt"); },
       "'{edx}' eval --gt '{dir}/gt' --est '{dir}/gt' --format tum --align se3", 1,
       "edx: error: {dir}/gt: is a directory (expected a trajectory file)"},
      {"c7_unknown_key_of_a_sweep_spec_is_blamed_on_the_spec",
       [](const fs::path& d) {
         write(d, "s.yaml",
               "base: {car}\ntrace: {golden}\nparameters:\n  backend.gemm_blok: {values: [2, "
               "4]}\nobjectives: [{minimize: dsp}]\n");
       },
       "'{edx}' sweep '{dir}/s.yaml' --db '{dir}/r.db'", 1,
       "edx: error: {dir}/s.yaml:4: backend.gemm_blok: unknown key"},
      {"c7_bad_workload_value_is_blamed_on_the_spec_before_any_trace",
       [](const fs::path& d) {
         write(d, "s.yaml",
               "base: {car}\nworkload: {mix: paper, frames: 16}\nparameters:\n"
               "  workload.features: {values: [200, 0]}\nobjectives: [{minimize: dsp}]\n");
       },
       "'{edx}' sweep '{dir}/s.yaml' --db '{dir}/r.db'", 1,
       "edx: error: {dir}/s.yaml:4: workload.features: expected an integer in [1, 100000], got "
       "'0'"},
      {"c7_workload_sweep_takes_no_trace",
       [](const fs::path& d) {
         write(d, "s.yaml",
               "base: {car}\nworkload: {speed: 3}\nparameters:\n"
               "  backend.units.gemm.block: {values: [2]}\nobjectives: [{minimize: dsp}]\n");
       },
       "'{edx}' sweep '{dir}/s.yaml' --db '{dir}/r.db' --trace '{golden}'", 1,
       "edx: error: {dir}/s.yaml: --trace: this sweep traces its workload points (workload:), it "
       "takes no trace"},
      {"c7_trace_store_that_is_a_file",
       [](const fs::path& d) {
         write(d, "store", "not a folder\n");
         write(d, "s.yaml",
               "base: {car}\nworkload: {mix: paper, frames: 16}\nparameters:\n"
               "  workload.features: {values: [200]}\nobjectives: [{minimize: dsp}]\n");
       },
       "'{edx}' sweep '{dir}/s.yaml' --db '{dir}/r.db' --trace-store '{dir}/store'", 1,
       "edx: error: {dir}/store: trace store: exists and is not a folder (give --trace-store a "
       "folder)"},
      {"c7_trace_store_under_a_file",
       [](const fs::path& d) {
         write(d, "f", "a file, not a folder\n");
         write(d, "w.yaml", "mix: paper\nframes: 16\nresolution: 320x240\n");
       },
       "'{edx}' simulate --config '{car}' --workload '{dir}/w.yaml' --seeds 1-2 --trace-store "
       "'{dir}/f/store'",
       1, "edx: error: {dir}/f/store: trace store: cannot create it: Not a directory"},
      {"c7_host_cost_table_of_other_features",
       [](const fs::path& d) {
         write(d, "costs.yaml",
               "suite: 1\nfrontend:\n  IF: {features: [call, area], costs: [1, 2], samples: 3, "
               "r2: 1, share: 1}\nbackend: {}\n");
       },
       "'{edx}' host-costs check --trace '{golden}' --costs '{dir}/costs.yaml'", 1,
       "edx: error: {dir}/costs.yaml:3: frontend.IF: features [call, area], but this edx models "
       "[call, pixels] (re-fit: edx host-costs fit)"},
      // A table lacking a kind the trace runs: the table is named, with the kind and the trace.
      {"c7_host_cost_table_without_a_kind_of_the_trace",
       [](const fs::path& d) {
         write(d, "costs.yaml",
               "suite: 1\nfrontend:\n  IF: {features: [call, pixels], costs: [1, 2], samples: 3, "
               "r2: 1, share: 1}\nbackend: {}\n");
       },
       "'{edx}' host-costs check --trace '{golden}' --costs '{dir}/costs.yaml'", 1,
       "edx: error: {dir}/costs.yaml: the host cost table (suite v1) has no costs for 'FD' (a "
       "frontend kind), which {golden} needs (re-fit it: edx host-costs fit, docs/MODEL.md \"Host "
       "CPU\")"},
      {"c7_host_cost_refit_of_a_kind_the_traces_lack", [](const fs::path&) {},
       "'{edx}' host-costs fit --trace '{golden}' --only no_such_kernel --out '{dir}/costs.yaml'",
       1, "edx: error: --only: kind 'no_such_kernel': the traces have no rows of it"},
      {"c7_tilde_is_described_as_nothing",
       [](const fs::path& d) {
         write(d, "p.yaml", "name: p\nbackend:\n  units: {gemm: {block: ~}}\n");
       },
       "'{edx}' simulate --config '{dir}/p.yaml' --trace '{golden}'", 1,
       "edx: error: {dir}/p.yaml:3: backend.units.gemm.block: expected an integer in [1, 256], got "
       "'nothing (~ or an empty value)'"},
      {"c7_unknown_device",
       [](const fs::path& d) { write(d, "p.yaml", "name: p\ndevice: virtex\n"); },
       "'{edx}' simulate --config '{dir}/p.yaml' --trace '{golden}' --out '{dir}/r.db'", 1,
       "edx: error: {dir}/p.yaml:2: platform.device: expected xc7v690t, zu9eg or zu9cg, got "
       "'virtex'"},
      {"c7_unknown_bundled_processor",
       [](const fs::path& d) {
         write(d, "p.yaml", "name: p\nhost:\n  kind: datasheet\n  processor: pentium4\n");
       },
       "'{edx}' simulate --config '{dir}/p.yaml' --trace '{golden}' --out '{dir}/r.db'", 1,
       "edx: error: {dir}/p.yaml:4: host.processor: expected a bundled processor "
       "(cortex_a53_zu9cg, cortex_a57_tx1, kaby_lake_4c, kryo_sd820), got 'pentium4'"},
      {"c7_coprocessor_running_scalar_work",
       [](const fs::path& d) {
         write(d, "p.yaml", "name: p\ncoprocessor:\n  kind: gpu\n  tasks: [FD, MO]\n");
       },
       "'{edx}' simulate --config '{dir}/p.yaml' --trace '{golden}' --out '{dir}/r.db'", 1,
       "edx: error: {dir}/p.yaml:4: coprocessor.tasks: expected rows a gpu runs, got 'MO', bound "
       "by scalar work"},
      {"c7_compared_baseline_without_a_config",
       [](const fs::path& d) {
         write(d, "t.yaml",
               "baselines:\n  - {name: one}\ntargets:\n  - {name: a, metric: x.y, paper: 1}\n");
       },
       "'{edx}' check --config '{car}' --trace '{golden}' --targets '{dir}/t.yaml'", 1,
       "edx: error: {dir}/t.yaml:2: baselines[].config: missing (expected a platform file)"},
      {"c7_characterize_out_is_a_file", [](const fs::path& d) { write(d, "f", "x\n"); },
       "'{edx}' characterize --seeds 1 --frames 8 --out '{dir}/f'", 1,
       "edx: error: {dir}/f: exists and is not a folder (--out)"},
      {"c7_characterization_not_json",
       [](const fs::path& d) { write(d, "c.json", "points: none\n"); },
       "'{edx}' check --config '{car}' --trace '{golden}' --characterization '{dir}/c.json'", 1,
       "edx: error: {dir}/c.json: expected JSON (edx characterize's characterization.json)"},
      {"c7_characterization_not_a_study",
       [](const fs::path& d) { write(d, "c.json", "{\"points\": {}}\n"); },
       "'{edx}' check --config '{car}' --trace '{golden}' --characterization '{dir}/c.json'", 1,
       "edx: error: {dir}/c.json: expected the characterization.json of edx characterize "
       "([json.exception.out_of_range.403] key 'scenarios' not found)"},
      {"c7_missing_platform_file", none,
       "'{edx}' simulate --config '{dir}/none.yaml' --trace '{golden}'", 1,
       "edx: error: {dir}/none.yaml: cannot read the platform file"},
      // A folder where a file is expected: named as a folder, at the one place each is opened.
      {"c7_platform_that_is_a_folder",
       [](const fs::path& d) { fs::create_directory(d / "p.yaml"); },
       "'{edx}' simulate --config '{dir}/p.yaml' --trace '{golden}'", 1,
       "edx: error: {dir}/p.yaml: is a directory (expected a platform file)"},
      {"c7_sweep_spec_that_is_a_folder",
       [](const fs::path& d) { fs::create_directory(d / "s.yaml"); },
       "'{edx}' sweep '{dir}/s.yaml' --db '{dir}/r.db'", 1,
       "edx: error: {dir}/s.yaml: is a directory (expected a sweep spec)"},
      {"c7_trace_that_is_a_folder", [](const fs::path& d) { fs::create_directory(d / "t.db"); },
       "'{edx}' simulate --config '{car}' --trace '{dir}/t.db'", 1,
       "edx: error: {dir}/t.db: is a directory (expected a trace file, written by edx trace)"},
      {"c7_missing_trace_file", none, "'{edx}' simulate --config '{car}' --trace '{dir}/none.db'",
       1, "edx: error: {dir}/none.db: no such trace file"},
      {"c7_trace_out_under_a_file", [](const fs::path& d) { write(d, "afile", "x"); },
       "'{edx}' trace --mix paper --frames 8 --resolution 320x240 --out '{dir}/afile/t.db'", 1,
       "edx: error: {dir}/afile/t.db: directory {dir}/afile is a file, not a directory"},
      {"c7_report_out_under_a_file",
       [](const fs::path& d) {
         write(d, "afile", "x");
         results_db(d, "r.db");
       },
       "'{edx}' report '{dir}/r.db' --out '{dir}/afile/report'", 1,
       "edx: error: {dir}/afile/report: cannot create its folder {dir}/afile (Not a directory)"},
      {"c7_missing_dataset_folder", none,
       "'{edx}' trace --dataset '{dir}/none' --format euroc --out '{dir}/t.db'", 1,
       "edx: error: {dir}/none: dataset folder not found"},
      // A trace simulated only at its own precision (the golden trace is fp64).
      {"c7_trace_of_another_precision", none,
       "'{edx}' simulate --config '{src}/configs/fp32/edx_car_fp32.yaml' --trace '{golden}'", 1,
       "edx: error: {golden}: the trace computed its backend kernels in fp64 (meta precision), "
       "but platform edx_car_fp32 computes in fp32 (backend.precision); trace with --precision "
       "fp32 or set backend.precision: fp64"},
      {"c7_characterize_on_a_platform_of_another_precision", none,
       "'{edx}' characterize --precision fp32 --out '{dir}/c'", 1,
       "edx: error: --precision fp32: platform edx_car computes in fp64 (backend.precision); give "
       "--platform a platform of backend.precision: fp32"},
      {"c7_unknown_option", none, "'{edx}' simulate --config '{car}' --trace '{golden}' --frob", 2,
       "edx: The following argument was not expected: --frob (see edx --help)"},
      // 8. One process per sweep: a sweep another live process holds is refused, naming it.
      {"c8_sweep_held_by_another_process",
       [](const fs::path& d) {
         results_db(d, "r.db");
         write(d, "s.yaml", sweep_spec());
         SQLite::Database db((d / "r.db").string(), SQLite::OPEN_READWRITE);
         db.exec(
             "CREATE TABLE sweep_locks (sweep_id TEXT PRIMARY KEY, pid INTEGER NOT NULL, host "
             "TEXT NOT NULL, started TEXT NOT NULL)");
         db.exec(expand("INSERT INTO sweep_locks VALUES ('s', 1, '{host}', '2026-11-26T00:00:00Z')",
                        d));
       },
       "'{edx}' sweep '{dir}/s.yaml' --db '{dir}/r.db'", 1,
       "edx: error: {dir}/r.db: sweep 's' is being run by process 1 on {host} since "
       "2026-11-26T00:00:00Z (wait for it, or delete its row from sweep_locks if that process is "
       "gone)"},
      // 9. A trajectory that goes back in time is refused at its line.
      {"c9_trajectory_going_back_in_time",
       [](const fs::path& d) {
         write(d, "gt.txt", "0 0 0 0 0 0 0 1\n2 1 0 0 0 0 0 1\n1 2 0 0 0 0 0 1\n3 3 0 0 0 0 0 1\n");
         write(d, "est.txt",
               "0 0 0 0 0 0 0 1\n1 1 0 0 0 0 0 1\n2 2 0 0 0 0 0 1\n3 3 0 0 0 0 0 1\n");
       },
       "'{edx}' eval --gt '{dir}/gt.txt' --est '{dir}/est.txt' --format tum --align se3", 1,
       "edx: error: {dir}/gt.txt:3: timestamp 1 s comes after timestamp 2 s on line 2: poses "
       "must be sorted"},
  };
}

/// Names a case in test output (the default would print its bytes).
void PrintTo(const BadInputCase& c, std::ostream* os) { *os << c.name; }

class BadInput : public ::testing::TestWithParam<BadInputCase> {};

TEST_P(BadInput, ExitsWithOneLineNamingTheFileAndChangesNothing) {
  const BadInputCase& c = GetParam();
  const TempDir dir;
  c.setup(dir.path());
  if (HasFatalFailure()) return;
  const auto before = snapshot(dir.path());
  const CommandResult r = run_command(expand(c.command, dir.path()));
  EXPECT_EQ(r.exit_code, c.exit_code) << r.err;
  EXPECT_EQ(r.err, expand(c.message, dir.path()) + "\n");
  EXPECT_EQ(snapshot(dir.path()), before) << "the command created, removed or changed a file";
}

INSTANTIATE_TEST_SUITE_P(Classes, BadInput, ::testing::ValuesIn(cases()),
                         [](const ::testing::TestParamInfo<BadInputCase>& info) {
                           return info.param.name;
                         });

// Class 9, the other side: a ground truth with repeated stamps (public RGB-D benchmark files
// have them) is read with a one-line warning naming the file and line, the first pose of each
// stamp kept (docs/EVAL.md).
TEST(BadInputAccepted, RepeatedGroundTruthStampsWarnAndAreEvaluated) {
  const TempDir dir;
  write(dir.path(), "gt.txt",
        "0 0 0 0 0 0 0 1\n1 1 0 0 0 0 0 1\n1 1 0 0 0 0 0 1\n2 2 0 0 0 0 0 1\n3 3 0 0 0 0 0 1\n");
  write(dir.path(), "est.txt",
        "0 0 0 0 0 0 0 1\n1 1 0 0 0 0 0 1\n2 2 0 0 0 0 0 1\n3 3 0 0 0 0 0 1\n");
  const CommandResult r = run_command(
      expand("'{edx}' eval --gt '{dir}/gt.txt' --est '{dir}/est.txt' --format tum --align se3 "
             "--json",
             dir.path()));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, expand("edx: warning: {dir}/gt.txt:3: 1 pose(s) repeat the previous pose's "
                          "stamp; the first of each kept\n",
                          dir.path()));
  EXPECT_NE(r.out.find("\"pairs\": 4"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace edx::testing
