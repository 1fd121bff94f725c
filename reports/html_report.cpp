#include "reports/html_report.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <tuple>

#include "arch/memory/bram.hpp"
#include "arch/results/causes.hpp"
#include "arch/results/schema.hpp"
#include "common/atomic_file.hpp"
#include "common/yaml_fields.hpp"
#include "reports/metrics.hpp"
#include "reports/paper_check.hpp"
#include "workloads/trace/reader.hpp"

extern char** environ;

namespace edx::reports {
namespace fs = std::filesystem;
namespace {

// One color per mode / part, the same in every plot (colour-blind safe Okabe-Ito palette).
constexpr const char* kPalette[] = {"#0072B2", "#E69F00", "#009E73", "#CC79A7",
                                    "#56B4E9", "#D55E00", "#F0E442", "#000000"};
constexpr const char* kBaselineColor = "#999999";
constexpr const char* kAcceleratedColor = "#0072B2";
/// The gnuplot terminal line: SVG, crisp at any zoom; `dynamic` lets the page scale it.
std::string svg_terminal(int width, int height) {
  return fmt::format(
      "set terminal svg size {},{} dynamic noenhanced font 'Sans,11' background '#ffffff'\n", width,
      height);
}
const std::string kTerminal = svg_terminal(960, 540);
constexpr const char* kPlotExtension = ".svg";

const char* mode_color(const std::string& mode) {
  if (mode == "registration") return kPalette[0];
  if (mode == "vio") return kPalette[1];
  if (mode == "slam") return kPalette[2];
  if (mode == "none") return kPalette[3];
  return kPalette[7];
}

std::string html_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

/// <th> cells of `columns` of a results table, headed as its declaration says
/// (arch/results/schema.cpp, docs/RESULTS.md).
std::string headings(const results::TableSpec& table,
                     std::initializer_list<std::string_view> columns) {
  std::string h;
  for (std::string_view c : columns) {
    h += fmt::format("<th>{}</th>", html_escape(table.columns[table.index_of(c)].heading()));
  }
  return h;
}

/// A gnuplot single-quoted string ('' escapes a quote).
std::string gp_quote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("''") : std::string(1, c);
  return out + "'";
}

std::string num(double v, int digits = 2) {
  if (!std::isfinite(v)) return "–";
  return fmt::format("{:.{}f}", v, digits);
}

std::string pct(double fraction) {
  return std::isfinite(fraction) ? fmt::format("{:.1f}%", 100 * fraction) : "–";
}

/// The text of `parts` streamed one after another (numbers as std::ostream prints them).
template <typename... Parts>
std::string cat(const Parts&... parts) {
  std::ostringstream text;
  (text << ... << parts);
  return text.str();
}

/// Writes a data file or gnuplot script of the report. A failed write is an error naming the file
/// and the system's reason (std::ofstream failed silently: gnuplot then plotted a truncated file,
/// or failed naming no reason).
void write_text(const fs::path& path, const std::string& text) { common::write_file(path, text); }

/// Runs `gnuplot script` without a shell; on failure throws with gnuplot's first error line.
void run_gnuplot(const std::string& gnuplot, const fs::path& script, const std::string& what) {
  const fs::path log = fs::path(script).replace_extension(".log");
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, log.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  std::string script_arg = script.string();
  std::vector<char*> argv = {const_cast<char*>(gnuplot.c_str()), script_arg.data(), nullptr};
  pid_t pid = 0;
  const int rc = posix_spawnp(&pid, gnuplot.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) throw std::runtime_error(fmt::format("cannot run {} for the {}", gnuplot, what));
  int status = 0;
  waitpid(pid, &status, 0);
  std::ifstream in(log);
  std::string line, first_error;
  while (std::getline(in, line)) {
    if (first_error.empty() && line.find_first_not_of(" ^") != std::string::npos &&
        line.find("\"") == std::string::npos) {
      first_error = line;
    }
    if (line.find("error") != std::string::npos) {
      first_error = line;
      break;
    }
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    throw std::runtime_error(
        fmt::format("gnuplot failed on the {} ({}): {}", what, script.string(), first_error));
  }
  fs::remove(log);
}

/// Empirical CDF points (sorted x, i/n).
std::vector<std::pair<double, double>> cdf(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  std::vector<std::pair<double, double>> pts;
  for (std::size_t i = 0; i < values.size(); ++i) {
    pts.emplace_back(values[i], double(i + 1) / double(values.size()));
  }
  return pts;
}

class RunReport {
 public:
  /// The run's whole-system timeline, written beside the report (`run<N>_timeline.json`) and
  /// linked; a line saying how to get one when the run has none.
  std::string timeline_link() const {
    if (run_.timelines.empty()) {
      return "<p class=\"cap\">No whole-system timeline stored for this run (<code>edx simulate "
             "--timeline T.json --out DB</code> keeps one).</p>\n";
    }
    const std::string file = prefix_ + "timeline.json";
    const results::TimelineRow& timeline = run_.timelines.front();
    common::write_file_atomically(dir_ / file, timeline.json);
    return fmt::format(
        "<p class=\"cap\">Whole-system timeline of the accelerated streamed run, frames {}–{}: "
        "<a href=\"{}\">{}</a> (Perfetto JSON: open it in https://ui.perfetto.dev; one track per "
        "frontend unit, link direction, host core, backend unit and queue).</p>\n",
        timeline.first_frame, timeline.first_frame + timeline.frames - 1, file, file);
  }

  RunReport(const RunData& run, std::size_t index, const fs::path& dir, const std::string& gnuplot,
            bool plot)
      : run_(run),
        prefix_(fmt::format("run{}_", index + 1)),
        dir_(dir),
        gnuplot_(gnuplot),
        plot_(plot),
        modes_(run_modes(run)) {}

  std::string html(std::vector<std::string>& images) {
    std::string h =
        fmt::format("<h2 id=\"{}\">Run {} — {} on {}</h2>\n", prefix_, html_escape(run_.run_id),
                    html_escape(run_.platform), html_escape(run_.trace));
    h += fmt::format(
        "<p>{} frames, offload policy {}. Baseline: CPU only; accelerated: the "
        "platform with its FPGA frontend and backend.</p>\n",
        run_.frames, html_escape(run_.policy));
    h += timeline_link();
    h += comparison_table();
    h += section("Latency CDF per mode", latency_cdf(), images,
                 "End-to-end latency per frame (frontend + backend); dashed: baseline (CPU), "
                 "solid: accelerated.");
    for (const std::string& mode : modes_) {
      h += section(fmt::format("Per-frame latency, {} frames", mode), per_frame(mode), images,
                   "Frames sorted by end-to-end latency, frontend (FE) and backend (BE) stacked "
                   "(paper Fig. 6-8 style).");
    }
    h += latency_table();
    h += section("Where each frame's latency went (critical-path attribution)", attribution_plot(),
                 images,
                 "Frames sorted by end-to-end latency (isolated run: a frame alone), its latency "
                 "split into the resources on its critical path, running or waiting, stacked "
                 "(docs/MODEL.md, \"Critical-path attribution\"; edx explain). Look for the "
                 "tallest band: the bottleneck.");
    h += cause_table();
    h += section("Backend kernel breakdown", breakdown_plot(), images,
                 "Mean backend time per frame split into the accelerable kernels and the rest "
                 "(host only), baseline (B) and accelerated (A) per mode.");
    h += breakdown_table();
    h += section("Throughput", fps_plot(), images,
                 "Frames per second back to back, without and with FE/BE pipelining.");
    h += throughput_table();
    h += section("Energy per frame", energy_plot(), images, "Mean energy per frame per mode.");
    h += energy_table();
    h += schedule_table();
    h += resources_table();
    return h;
  }

 private:
  std::string section(const std::string& title, const std::string& image,
                      std::vector<std::string>& images, const std::string& caption) {
    std::string h = fmt::format("<h3>{}</h3>\n<p class=\"cap\">{}</p>\n", html_escape(title),
                                html_escape(caption));
    if (!image.empty()) {
      images.push_back(image);
      h += fmt::format("<img src=\"{0}\" alt=\"{1}\">\n", image, html_escape(title));
    }
    return h;
  }

  /// Writes `data` and `script` (with the terminal and output set) and runs gnuplot.
  std::string plot(const std::string& name, const std::string& data, const std::string& script,
                   const std::string& what) {
    if (!plot_) return "";
    const std::string png = prefix_ + name + kPlotExtension;
    const fs::path dat = dir_ / (prefix_ + name + ".dat");
    const fs::path gp = dir_ / (prefix_ + name + ".gp");
    write_text(dat, data);
    write_text(gp, cat(kTerminal, "set output ", gp_quote((dir_ / png).string()), "\n",
                       "datafile = ", gp_quote(dat.string()), "\n", script));
    run_gnuplot(gnuplot_, gp, what);
    return png;
  }

  std::vector<double> values(const std::string& variant, const std::string& mode,
                             double FrameRow::*field) const {
    std::vector<double> v;
    for (const FrameRow& f : run_.frame_rows) {
      if (f.variant == variant && (mode == "all" || f.mode == mode)) v.push_back(f.*field);
    }
    return v;
  }

  std::string latency_cdf() {
    std::string data, plots;
    int block = 0;
    for (const std::string& mode : modes_) {
      for (const char* variant : {"baseline", "accelerated"}) {
        data += fmt::format("# {} {}\n", mode, variant);
        for (const auto& [x, y] : cdf(values(variant, mode, &FrameRow::e2e_ms))) {
          data += fmt::format("{:.6f} {:.6f}\n", x, y);
        }
        data += "\n\n";
        const bool base = std::string(variant) == "baseline";
        plots += fmt::format(
            "{}datafile index {} using 1:2 with steps lw 2 dt {} lc rgb '{}' title '{} {}'",
            plots.empty() ? "plot " : ", \\\n     ", block++, base ? 2 : 1, mode_color(mode), mode,
            base ? "baseline (CPU)" : "accelerated");
      }
    }
    const std::string script =
        "set title 'End-to-end latency CDF per mode'\n"
        "set xlabel 'End-to-end latency per frame (ms)'\n"
        "set ylabel 'Fraction of frames'\nset yrange [0:1.02]\nset xrange [0:*]\n"
        "set grid\nset key right bottom\n" +
        plots + "\n";
    return plot("latency_cdf", data, script, "latency CDF");
  }

  std::string per_frame(const std::string& mode) {
    std::string data;
    double ymax = 0;
    std::size_t n = 0;
    for (const char* variant : {"baseline", "accelerated"}) {
      std::vector<const FrameRow*> rows;
      for (const FrameRow& f : run_.frame_rows) {
        if (f.variant == variant && f.mode == mode) rows.push_back(&f);
      }
      std::stable_sort(rows.begin(), rows.end(),
                       [](const FrameRow* a, const FrameRow* b) { return a->e2e_ms < b->e2e_ms; });
      n = std::max(n, rows.size());
      data += fmt::format("# {}: rank frontend_ms backend_ms frame_id\n", variant);
      for (std::size_t i = 0; i < rows.size(); ++i) {
        data += fmt::format("{} {:.6f} {:.6f} {}\n", i + 1, rows[i]->frontend_ms,
                            rows[i]->backend_ms, rows[i]->frame_id);
        ymax = std::max(ymax, rows[i]->frontend_ms + rows[i]->backend_ms);
      }
      data += "\n\n";
    }
    std::string script = fmt::format(
        "set multiplot layout 1,2 title 'Per-frame latency, {0} mode (frames sorted by "
        "end-to-end latency)'\n"
        "set style fill solid 0.9 noborder\nset boxwidth 1.0 absolute\nset grid ytics\n"
        "set yrange [0:{1:.3f}]\nset xrange [0.5:{2:.1f}]\nset xlabel 'Frame rank'\n"
        "set ylabel 'Latency (ms)'\nset key left top\n",
        mode, 1.08 * ymax, double(n) + 0.5);
    int block = 0;
    for (const char* title : {"Baseline (CPU)", "Accelerated"}) {
      script += fmt::format(
          "set title '{0}'\n"
          "plot datafile index {1} using 1:($2+$3) with boxes lc rgb '{2}' title 'Backend (BE)', "
          "\\\n     '' index {1} using 1:2 with boxes lc rgb '{3}' title 'Frontend (FE)'\n",
          title, block++, kPalette[1], kPalette[0]);
    }
    script += "unset multiplot\n";
    return plot("frames_" + mode, data, script, "per-frame latency of " + mode);
  }

  std::string breakdown_plot() {
    const std::vector<BackendBreakdown> bars = backend_breakdown(run_);
    if (bars.empty()) return "";
    const std::size_t parts = bars.front().parts.size();
    std::string data = "# x label cumulative parts (ms per frame)\n";
    double x = 0;
    std::string xtics, mode_labels;
    for (std::size_t i = 0; i < bars.size(); ++i) {
      if (i > 0 && bars[i].mode != bars[i - 1].mode) x += 0.8;  // gap between modes
      double sum = 0;
      data += fmt::format("{:.2f}", x);
      for (const auto& [name, ms] : bars[i].parts) {
        sum += std::max(0.0, ms);
        data += fmt::format(" {:.6f}", sum);
      }
      data += "\n";
      const bool base = bars[i].variant == "baseline";
      xtics += fmt::format("{}'{}' {:.2f}", xtics.empty() ? "" : ", ", base ? "B" : "A", x);
      // The mode's name centred under its two bars.
      if (!base) {
        mode_labels += fmt::format("set label {} at {:.2f}, graph -0.09 center\n",
                                   gp_quote(bars[i].mode), x - 0.5);
      }
      x += 1;
    }
    std::string script =
        "set title 'Backend time per frame by kernel: B = baseline (CPU), A = accelerated'\n"
        "set ylabel 'Mean backend time per frame (ms)'\nset style fill solid 0.9 border -1\n"
        "set boxwidth 0.8 absolute\nset grid ytics\nset yrange [0:*]\nset key outside right top\n"
        "set bmargin 4\nset xtics (" +
        xtics + ") nomirror\nset xrange [-0.7:" + fmt::format("{:.2f}", x - 0.3) + "]\n" +
        mode_labels;
    // Tallest (cumulative) first so each smaller stack is drawn on top of it.
    for (std::size_t p = parts; p-- > 0;) {
      script += fmt::format(
          "{}datafile using 1:{} with boxes lc rgb '{}' title {}",
          p + 1 == parts ? "plot " : ", \\\n     ", p + 2,
          p + 1 == parts ? "#BBBBBB" : kPalette[p % 7],
          gp_quote(bars.front().parts[p].first == "other" ? "other backend (host)"
                                                          : bars.front().parts[p].first));
    }
    return plot("backend_breakdown", data, script + "\n", "backend breakdown");
  }

  /// Two bars (baseline, accelerated) per group with their values above them.
  std::string bars(const std::string& name, const std::string& title, const std::string& ylabel,
                   const std::vector<std::tuple<std::string, double, double>>& groups, int digits) {
    std::string data = "# group baseline accelerated\n";
    double ymax = 0;
    for (const auto& [label, base, acc] : groups) {
      data += fmt::format("\"{}\" {:.6f} {:.6f}\n", label, base, acc);
      ymax = std::max({ymax, base, acc});
    }
    const std::string script = fmt::format(
        "set title '{0}'\nset ylabel '{1}'\nset style data histograms\n"
        "set style histogram cluster gap 1\nset style fill solid 0.9 border -1\n"
        "set boxwidth 1.0 relative\nset grid ytics\nset yrange [0:{2:.4f}]\nset key left top\n"
        "set xtics nomirror\nset xrange [-0.6:{6:.1f}]\n"
        "plot datafile using 2:xtic(1) lc rgb '{3}' title 'Baseline (CPU)', \\\n"
        "     '' using 3 lc rgb '{4}' title 'Accelerated', \\\n"
        "     '' using ($0-1.0/6):2:(sprintf('%.{5}f', $2)) with labels offset 0,0.8 notitle, \\\n"
        "     '' using ($0+1.0/6):3:(sprintf('%.{5}f', $3)) with labels offset 0,0.8 notitle\n",
        title, ylabel, 1.18 * std::max(ymax, 1e-9), kBaselineColor, kAcceleratedColor, digits,
        double(groups.size()) - 0.4);
    return plot(name, data, script, title);
  }

  std::string fps_plot() {
    const ThroughputRow* base = nullptr;
    const ThroughputRow* acc = nullptr;
    for (const ThroughputRow& t : run_.throughput) {
      if (t.variant == "baseline") base = &t;
      if (t.variant == "accelerated") acc = &t;
    }
    if (!base || !acc) return "";
    return bars(
        "fps", "Throughput", "Frames per second (FPS)",
        {{"without FE/BE pipelining", base->fps_without_pipelining, acc->fps_without_pipelining},
         {"with FE/BE pipelining", base->fps_with_pipelining, acc->fps_with_pipelining}},
        1);
  }

  std::string energy_plot() {
    std::vector<std::tuple<std::string, double, double>> groups;
    std::vector<std::string> modes = modes_;
    modes.push_back("all");
    for (const std::string& mode : modes) {
      double base = NAN, acc = NAN;
      for (const EnergyRow& e : run_.energy) {
        if (e.mode != mode) continue;
        (e.variant == "baseline" ? base : acc) = e.mean_j;
      }
      if (std::isfinite(base) && std::isfinite(acc)) groups.emplace_back(mode, base, acc);
    }
    if (groups.empty()) return "";
    return bars("energy", "Energy per frame", "Mean energy per frame (J)", groups, 3);
  }

  std::string comparison_table() const {
    if (!run_.summary.contains("comparison")) return "";
    std::string h =
        "<h3>Baseline vs accelerated</h3>\n<table><tr><th>mode</th><th>e2e speedup</th>"
        "<th>frontend speedup</th><th>backend speedup</th><th>backend latency reduction</th>"
        "<th>e2e SD reduction</th><th>backend SD reduction</th><th>energy reduction</th></tr>\n";
    std::vector<std::string> modes = modes_;
    modes.push_back("all");
    for (const std::string& mode : modes) {
      if (!run_.summary["comparison"].contains(mode)) continue;
      const nlohmann::json& c = run_.summary["comparison"][mode];
      const auto get = [&](const char* k) { return c.value(k, NAN); };
      h += fmt::format(
          "<tr><td>{}</td><td>{}×</td><td>{}×</td><td>{}×</td><td>{}</td><td>{}</td><td>{}</td>"
          "<td>{}</td></tr>\n",
          mode, num(get("e2e_speedup")), num(get("frontend_speedup")), num(get("backend_speedup")),
          pct(get("backend_latency_reduction")), pct(get("e2e_sd_reduction")),
          pct(get("backend_sd_reduction")), pct(get("energy_reduction")));
    }
    return h + "</table>\n";
  }

  /// Per variant, frames sorted by latency, each stacked by the resources of its causes (the
  /// isolated run's frame_causes): the accelerated variant's six largest resources, the rest as
  /// "other". Empty without per-frame attribution.
  std::string attribution_plot() {
    const auto summary = nlohmann::json::json_pointer("/accelerated/attribution/isolated/all");
    if (run_.frame_causes.empty() || !run_.summary.contains(summary)) return "";
    std::vector<std::string> shown;
    for (const nlohmann::json& r : run_.summary[summary]["resources"]) {
      if (shown.size() < 6) shown.push_back(r["name"].get<std::string>());
    }
    for (const char* variant : {"baseline", "accelerated"}) {  // the baseline's largest too
      const auto p =
          nlohmann::json::json_pointer(fmt::format("/{}/attribution/isolated/all", variant));
      if (!run_.summary.contains(p) || run_.summary[p]["resources"].empty()) continue;
      const std::string top = run_.summary[p]["resources"][0]["name"];
      if (std::find(shown.begin(), shown.end(), top) == shown.end()) shown.push_back(top);
    }
    const std::size_t bands = shown.size() + 1;  // + other
    std::string data;
    double ymax = 0;
    std::size_t n = 0;
    for (const char* variant : {"baseline", "accelerated"}) {
      struct Frame {
        double latency;
        std::vector<double> band;
      };
      const results::CauseTable table =
          results::cause_table_of(run_.frame_causes, run_.frame_rows, variant, "isolated");
      std::vector<std::size_t> band_of_cause;  // each column's band ("other": shown.size())
      for (const std::string& cause : table.causes) {
        const auto at =
            std::find(shown.begin(), shown.end(), std::string(results::cause_resource(cause)));
        band_of_cause.push_back(static_cast<std::size_t>(at - shown.begin()));
      }
      std::vector<Frame> frames;
      for (std::size_t row = 0; row < table.frames.size(); ++row) {
        if (table.frames[row].dropped) continue;
        Frame f{table.frames[row].latency_ms, std::vector<double>(bands, 0.0)};
        for (std::size_t c = 0; c < table.causes.size(); ++c) {
          f.band[band_of_cause[c]] += table.at(row, c);
        }
        frames.push_back(std::move(f));
      }
      std::stable_sort(frames.begin(), frames.end(),
                       [](const Frame& a, const Frame& b) { return a.latency < b.latency; });
      n = std::max(n, frames.size());
      data += fmt::format("# {}: rank, cumulative ms of each band\n", variant);
      for (std::size_t i = 0; i < frames.size(); ++i) {
        data += fmt::format("{}", i + 1);
        double sum = 0;
        for (double ms : frames[i].band) data += fmt::format(" {:.6f}", sum += ms);
        data += "\n";
        ymax = std::max(ymax, sum);
      }
      data += "\n\n";
    }
    std::string script = fmt::format(
        "set multiplot layout 1,2 title 'Critical-path attribution per frame (frames sorted by "
        "latency)'\nset style fill solid 0.9 noborder\nset boxwidth 1.0 absolute\n"
        "set grid ytics\nset yrange [0:{:.3f}]\nset xrange [0.5:{:.1f}]\n"
        "set xlabel 'Frame rank'\nset ylabel 'Latency (ms)'\nset key left top font ',8'\n",
        1.15 * ymax, double(n) + 0.5);
    int block = 0;
    for (const char* title : {"Baseline (CPU)", "Accelerated"}) {
      script += fmt::format("set title '{}'\nplot", title);
      // The tallest cumulative column first, so each band shows in front of the next.
      for (std::size_t b = bands; b-- > 0;) {
        script += fmt::format("{} datafile index {} using 1:{} with boxes lc rgb '{}' title {}",
                              b + 1 == bands ? "" : ", \\\n    ", block, b + 2,
                              b + 1 == bands ? "#BBBBBB" : kPalette[b % 8],
                              gp_quote(b + 1 == bands ? std::string("other") : shown[b]));
      }
      script += "\n";
      ++block;
    }
    script += "unset multiplot\n";
    return plot("attribution", data, script, "critical-path attribution");
  }

  /// The per-mode cause table of the run summary's attribution: per variant and run, each
  /// cause's mean ms (share of the mode's latency) by mode, and each mode's bottleneck.
  std::string cause_table() const {
    std::string h;
    for (const char* variant : {"accelerated", "baseline"}) {
      for (const char* run : {"isolated", "streamed"}) {
        const auto p =
            nlohmann::json::json_pointer(fmt::format("/{}/attribution/{}", variant, run));
        if (!run_.summary.contains(p) || !run_.summary[p].contains("all")) continue;
        const nlohmann::json& modes = run_.summary[p];
        std::vector<std::string> names;
        for (const auto& [mode, m] : modes.items()) {
          if (mode != "all") names.push_back(mode);
        }
        names.push_back("all");
        h += fmt::format(
            "<h3>Causes, {} variant, {} run</h3>\n<p class=\"cap\">Mean ms per frame of each "
            "cause (share of the mode's mean latency); {}.</p>\n<table><tr><th>cause</th>",
            variant, run,
            std::string(run) == "isolated"
                ? "a frame alone: the paper's latency"
                : "frames at the sensor rate or back to back: queueing included");
        for (const std::string& m : names) h += "<th>" + html_escape(m) + "</th>";
        h += "</tr>\n<tr><td>latency</td>";
        for (const std::string& m : names)
          h += "<td>" + num(modes[m]["latency_ms"].get<double>(), 3) + "</td>";
        h += "</tr>\n";
        for (const nlohmann::json& c : modes["all"]["causes"]) {
          const std::string cause = c["name"];
          h += "<tr><td>" + html_escape(cause) + "</td>";
          for (const std::string& m : names) {
            std::string cell = "–";
            for (const nlohmann::json& x : modes[m]["causes"]) {
              if (x["name"] == cause) {
                cell = fmt::format("{} ({})", num(x["mean_ms"].get<double>(), 3),
                                   pct(x["share"].get<double>()));
              }
            }
            h += "<td>" + cell + "</td>";
          }
          h += "</tr>\n";
        }
        h += "<tr><td><b>bottleneck</b></td>";
        for (const std::string& m : names) {
          h += "<td><b>" + html_escape(modes[m]["bottleneck"].get<std::string>()) + "</b></td>";
        }
        h += "</tr>\n</table>\n";
      }
    }
    return h;
  }

  std::string latency_table() const {
    std::string h = fmt::format(
        "<h3>Latency statistics</h3>\n<table><tr>{}</tr>\n",
        headings(results::latency_table().spec, {"variant", "mode", "stage", "count", "mean", "sd",
                                                 "rsd", "p50", "p90", "p99", "max"}));
    for (const LatencyRow& l : run_.latency) {
      h += fmt::format(
          "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td>"
          "<td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
          l.variant, l.mode, l.stage, l.count, num(l.mean), num(l.sd), pct(l.rsd), num(l.p50),
          num(l.p90), num(l.p99), num(l.max));
    }
    return h + "</table>\n";
  }

  std::string breakdown_table() const {
    const std::vector<BackendBreakdown> rows = backend_breakdown(run_);
    if (rows.empty()) return "";
    std::string h = "<table><tr><th>mode</th><th>variant</th><th>frames</th>";
    for (const auto& [name, ms] : rows.front().parts)
      h += "<th>" + html_escape(name) + " (ms)</th>";
    h += "<th>backend total (ms)</th></tr>\n";
    for (const BackendBreakdown& b : rows) {
      h += fmt::format("<tr><td>{}</td><td>{}</td><td>{}</td>", b.mode, b.variant, b.frames);
      double total = 0;
      for (const auto& [name, ms] : b.parts) {
        h += "<td>" + num(ms, 3) + "</td>";
        total += ms;
      }
      h += "<td>" + num(total, 3) + "</td></tr>\n";
    }
    return h + "</table>\n";
  }

  std::string throughput_table() const {
    std::string h =
        fmt::format("<table><tr>{}</tr>\n",
                    headings(results::throughput_table().spec,
                             {"variant", "fps_without_pipelining", "fps_with_pipelining"}));
    for (const ThroughputRow& t : run_.throughput) {
      h += fmt::format("<tr><td>{}</td><td>{}</td><td>{}</td></tr>\n", t.variant,
                       num(t.fps_without_pipelining, 1), num(t.fps_with_pipelining, 1));
    }
    return h + "</table>\n";
  }

  std::string energy_table() const {
    std::string h = fmt::format("<table><tr>{}</tr>\n",
                                headings(results::energy_table().spec,
                                         {"variant", "mode", "mean_j", "sd_j", "p99_j", "max_j"}));
    for (const EnergyRow& e : run_.energy) {
      h += fmt::format(
          "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
          e.variant, e.mode, num(e.mean_j, 3), num(e.sd_j, 3), num(e.p99_j, 3), num(e.max_j, 3));
    }
    return h + "</table>\n";
  }

  std::string schedule_table() const {
    if (run_.schedule.empty()) return "";
    const nlohmann::json derived = run_metrics(run_)["derived"];
    std::string h = fmt::format(
        "<h3>Offload scheduler (evaluation frames)</h3>\n<table><tr>{}<th>kernel speedup (fitting "
        "invocations)</th></tr>\n",
        headings(results::schedule_table().spec,
                 {"kernel", "invocations", "offloaded", "host_only_s", "always_s", "policy_s",
                  "oracle_s", "r_squared_train", "r_squared_eval", "gap_to_oracle"}));
    for (const ScheduleRow& s : run_.schedule) {
      const auto speedup = metric_at(derived, "kernels." + s.kernel + ".speedup");
      h += fmt::format(
          "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td>"
          "<td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
          s.kernel, s.invocations, s.offloaded, num(s.host_only_s, 4),
          std::isfinite(s.always_s) ? num(s.always_s, 4) : "does not fit", num(s.policy_s, 4),
          num(s.oracle_s, 4), num(s.r_squared_train, 3), num(s.r_squared_eval, 3),
          pct(s.gap_to_oracle), speedup ? num(*speedup) + "×" : "–");
    }
    return h + "</table>\n";
  }

  std::string resources_table() const {
    if (run_.resources.empty()) return "";
    std::string h = fmt::format("<h3>FPGA resources</h3>\n<table><tr>{}</tr>\n",
                                headings(results::resources_table().spec,
                                         {"entry", "grp", "kind", "lut", "ff", "dsp", "bram",
                                          "ns_lut", "ns_ff", "ns_dsp", "ns_bram"}));
    for (const ResourceRow& r : run_.resources) {
      h += fmt::format(
          "<tr{}><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td>"
          "<td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
          r.entry == "total" ? " class=\"total\"" : "", html_escape(r.entry), html_escape(r.group),
          html_escape(r.kind), num(r.lut, 0), num(r.ff, 0), num(r.dsp, 0), num(r.bram, 1),
          num(r.ns_lut, 0), num(r.ns_ff, 0), num(r.ns_dsp, 0), num(r.ns_bram, 1));
    }
    h += "</table>\n";
    h += device_table();
    // The model's own comparison with the paper's Table III (summary_json, resources): Edx-Car's
    // figures, so only for an Edx-Car run.
    const nlohmann::json& res = run_.summary.value("resources", nlohmann::json::object());
    if (!is_edx_car_run(run_)) {
      h += fmt::format(
          "<p class=\"cap\">Table III (the paper's Edx-Car resources) is compared only for "
          "Edx-Car runs (platform edx_car on the {}).</p>\n",
          arch::Device::xc7v690t().name);
    } else if (res.contains("edx_car_table_iii") && res["edx_car_table_iii"].is_array()) {
      h += "<table><tr><th>Table III figure (Edx-Car)</th><th>paper</th><th>simulated</th>"
           "<th>error</th></tr>\n";
      for (const nlohmann::json& c : res["edx_car_table_iii"]) {
        h += fmt::format("<tr><td>{}</td><td>{:.4g}</td><td>{:.4g}</td><td>{:+.1f}%</td></tr>\n",
                         html_escape(c.value("figure", std::string())), c.value("paper", NAN),
                         c.value("simulated", NAN), 100 * c.value("relative_error", NAN));
      }
      h += "</table>\n";
    }
    return h;
  }

  /// The design's totals against its own device's capacity (the platform's `device`, as the
  /// summary names it; capacities from the datasheet, arch/memory/bram.hpp Device): used, N.S.,
  /// capacity and utilization per resource. Without a known device: the summary's utilization.
  std::string device_table() const {
    const nlohmann::json& res = run_.summary.value("resources", nlohmann::json::object());
    if (!res.is_object() || !res.contains("total")) return "";
    const std::string name = res.value("device", std::string());
    const std::optional<arch::Device> device = arch::Device::find(name);
    const auto number = [&res](const char* group, const char* key) {
      const nlohmann::json& g = res.value(group, nlohmann::json::object());
      return g.is_object() && g.contains(key) && g[key].is_number() ? g[key].get<double>() : NAN;
    };
    struct Row {
      const char* label;
      const char* key;
      std::int64_t capacity;
    };
    const std::vector<Row> rows = {
        {"LUT", "lut", device ? device->luts : 0},
        {"FF", "ff", device ? device->flip_flops : 0},
        {"DSP", "dsp", device ? device->dsps : 0},
        {"BRAM36 blocks", "bram_blocks", device ? device->bram36_blocks : 0}};
    std::string h = fmt::format(
        "<p class=\"cap\">The design against its own device, {} (<code>device:</code> of the "
        "platform{}). A row over 100 % utilization is tinted: the design does not fit (N.S.: the "
        "paper's non-shared comparison, not a design to "
        "build).</p>\n<table><tr><th>resource</th><th>used</th>"
        "<th>N.S. used</th><th>device capacity</th><th>utilization</th><th>N.S. utilization</th>"
        "</tr>\n",
        html_escape(name.empty() ? std::string("unknown") : name),
        device ? "; capacities: " + html_escape(device->source) : "");
    for (const Row& r : rows) {
      const double used = number("total", r.key), ns = number("ns_total", r.key);
      const double util = device ? used / double(r.capacity) : number("utilization", r.key);
      h += fmt::format(
          "<tr{}><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
          util > 1 ? " class=\"miss\"" : "", r.label, num(used, 0), num(ns, 0),
          device ? fmt::format("{}", r.capacity) : std::string("–"), pct(util),
          device ? pct(ns / double(r.capacity)) : std::string("–"));
    }
    return h + fmt::format("</table>\n<p>BRAM {} MiB (N.S. {} MiB).</p>\n",
                           num(res.value("bram_mib", NAN)), num(res.value("ns_bram_mib", NAN)));
  }

  const RunData& run_;
  std::string prefix_;
  fs::path dir_;
  std::string gnuplot_;
  bool plot_;
  std::vector<std::string> modes_;
};

std::optional<double> sweep_value(const SweepPoint& p, const std::string& metric) {
  if (!p.metrics.is_object() || !p.metrics.contains(metric) || !p.metrics[metric].is_number()) {
    return std::nullopt;
  }
  return p.metrics[metric].get<double>();
}

/// A sweep point's parameters, "key = value, ...".
std::string parameters_text(const SweepPoint& p) {
  std::string text;
  if (!p.parameters.is_object()) return text;
  for (const auto& [k, v] : p.parameters.items()) {
    text +=
        (text.empty() ? "" : ", ") + k + " = " + (v.is_string() ? v.get<std::string>() : v.dump());
  }
  return text;
}

/// Whether a sweep metric is an accuracy metric (ATE RMSE: ate_rmse, ate_rmse_vio, ...;
/// docs/SWEEPS.md "Accuracy").
bool is_accuracy_metric(const std::string& metric) { return metric.starts_with("ate_rmse"); }

/// The accuracy-latency-resources front of a sweep with an accuracy objective and two others
/// (docs/REPORTS.md): the accuracy objective against the first other one, coloured by the
/// second; grey: feasible points off the front; the front's points by their colour. Empty when
/// the sweep has no such three objectives.
std::string accuracy_front_html(const SweepData& sweep, int index, const fs::path& dir,
                                const std::string& gnuplot, bool plot,
                                std::vector<std::string>& images) {
  std::optional<std::size_t> accuracy;
  std::vector<std::size_t> others;
  for (std::size_t i = 0; i < sweep.objectives.size(); ++i) {
    if (!accuracy && is_accuracy_metric(sweep.objectives[i].metric)) {
      accuracy = i;
    } else {
      others.push_back(i);
    }
  }
  if (!accuracy || others.size() < 2) return {};
  const std::string& a = sweep.objectives[*accuracy].metric;
  const std::string& x = sweep.objectives[others[0]].metric;
  const std::string& c = sweep.objectives[others[1]].metric;
  // Blocks: 0 feasible off the front, 1 the front (x y colour).
  std::string blocks[2];
  std::size_t on_front = 0;
  for (const SweepPoint& p : sweep.points) {
    const auto vx = sweep_value(p, x), vy = sweep_value(p, a), vc = sweep_value(p, c);
    if (!p.feasible || !vx || !vy || !vc) continue;
    blocks[p.pareto ? 1 : 0] += fmt::format("{:.9g} {:.9g} {:.9g}\n", *vx, *vy, *vc);
    on_front += p.pareto ? 1 : 0;
  }
  std::string h = fmt::format(
      "<h4>Accuracy, latency and resources</h4>\n<p class=\"cap\">The front of the three "
      "objectives: {} (m) against {}, coloured by {}; {} designs on the front, grey: feasible "
      "designs off it. Each design's ATE is its workload point's (the trace's), its latency and "
      "resources its platform's on that trace.</p>\n",
      html_escape(a), html_escape(x), html_escape(c), on_front);
  if (!plot) return h;
  std::string dat;
  for (const std::string& b : blocks)
    dat += "# block\n" + (b.empty() ? "nan nan nan\n" : b) + "\n\n";
  const std::string stem = fmt::format("sweep{}_accuracy", index);
  const std::string image = stem + kPlotExtension;
  write_text(dir / (stem + ".dat"), dat);
  write_text(
      dir / (stem + ".gp"),
      cat(kTerminal, "set output ", gp_quote((dir / image).string()), "\n", "set title ",
          gp_quote("Sweep " + sweep.sweep_id + ": accuracy-latency-resources front"),
          "\nset xlabel ", gp_quote(x), "\nset ylabel ", gp_quote(a + " (m)"), "\nset cblabel ",
          gp_quote(c), "\nset palette defined (0 '#0072B2', 1 '#009E73', 2 '#E69F00', 3 '#D55E00')",
          "\nset offsets graph 0.05, graph 0.05, graph 0.05, graph 0.05",
          "\nset grid\nset key outside right top\n", "plot ",
          gp_quote((dir / (stem + ".dat")).string()),
          " index 0 using 1:2 with points pt 7 ps 0.8 lc rgb '#BBBBBB' title 'feasible', "
          "'' index 1 using 1:2:3 with points pt 7 ps 1.6 lc palette title 'front'\n"));
  run_gnuplot(gnuplot, dir / (stem + ".gp"), "sweep " + sweep.sweep_id + " accuracy plot");
  images.push_back(image);
  return h + fmt::format("<img src=\"{}\" alt=\"Accuracy-latency-resources front\">\n", image);
}

/// The points of a sweep and their Pareto front (sweep_points.pareto, as `edx sweep` stored it):
/// one plot per pair (first objective, each other objective); one objective: value per point.
/// A search's convergence: the hypervolume of the feasible front found by each generation
/// (a plot) and the table of sweep_generations.
std::string convergence_html(const SweepData& sweep, int index, const fs::path& dir,
                             const std::string& gnuplot, bool plot,
                             std::vector<std::string>& images) {
  std::string h = fmt::format(
      "<p class=\"cap\">Search: {} generations, {} designs simulated. The hypervolume of the "
      "feasible front found so far should rise and level off; a curve still rising at the last "
      "generation says the search stopped early.</p>\n",
      sweep.generations.back().generation, sweep.generations.back().evaluations);
  if (plot) {
    std::string dat = "# generation evaluations hypervolume\n";
    for (const SweepGeneration& g : sweep.generations) {
      dat += fmt::format("{} {} {:.9g}\n", g.generation, g.evaluations, g.hypervolume);
    }
    const std::string stem = fmt::format("sweep{}_convergence", index);
    const std::string image = stem + kPlotExtension;
    write_text(dir / (stem + ".dat"), dat);
    write_text(
        dir / (stem + ".gp"),
        cat(kTerminal, "set output ", gp_quote((dir / image).string()), "\n", "set title ",
            gp_quote("Sweep " + sweep.sweep_id + ": hypervolume per generation"),
            "\nset xlabel 'Designs simulated'\nset ylabel 'Hypervolume of the feasible front'",
            "\nset grid\nunset key\nplot ", gp_quote((dir / (stem + ".dat")).string()),
            " using 2:3 with linespoints pt 7 lw 2 lc rgb '#0072B2'\n"));
    run_gnuplot(gnuplot, dir / (stem + ".gp"), "sweep " + sweep.sweep_id + " convergence plot");
    images.push_back(image);
    h += fmt::format("<img src=\"{}\" alt=\"hypervolume per generation\">\n", image);
  }
  h += fmt::format("<table><tr>{}</tr>\n",
                   headings(results::sweep_generations_table().spec,
                            {"generation", "evaluations", "front_size", "hypervolume"}));
  for (const SweepGeneration& g : sweep.generations) {
    h += fmt::format("<tr><td>{}</td><td>{}</td><td>{}</td><td>{:.6g}</td></tr>\n", g.generation,
                     g.evaluations, g.front_size, g.hypervolume);
  }
  return h + "</table>\n";
}

/// A workload sweep's points side by side: frame rate (FE/BE pipelined) and energy per frame of
/// the CPU baseline and the accelerated platform, one group per point, labelled with its
/// workload.* values (and its platform values when the sweep varies both).
std::string workload_html(const ResultsData& data, const SweepData& sweep, int index,
                          const fs::path& dir, const std::string& gnuplot, bool plot,
                          std::vector<std::string>& images) {
  std::string dat = "# label baseline_fps accelerated_fps baseline_mj accelerated_mj\n";
  std::string rows;
  std::size_t plotted = 0;
  bool platform_varies = false;
  for (const SweepPoint& p : sweep.points) {
    for (const auto& [k, v] : p.parameters.items()) platform_varies |= !k.starts_with("workload.");
  }
  for (const SweepPoint& p : sweep.points) {
    std::string label, platform;  // workload values first
    for (const auto& [k, v] : p.parameters.items()) {
      const bool workload = k.starts_with("workload.");
      std::string& to = workload ? label : platform;
      if (!to.empty()) to += ' ';
      to += fmt::format("{}={}", k.substr(k.rfind('.') + 1),
                        v.is_string() ? v.get<std::string>() : v.dump());
    }
    if (platform_varies && !platform.empty()) label += label.empty() ? platform : ' ' + platform;
    const RunData* run = p.error.empty() ? data.find(p.run_id) : nullptr;
    const auto number = [&](const char* pointer) {
      const nlohmann::json::json_pointer ptr(pointer);
      return run && run->summary.contains(ptr) && run->summary[ptr].is_number()
                 ? run->summary[ptr].get<double>()
                 : NAN;
    };
    const double fps[2] = {number("/baseline/fps_with_pipelining"),
                           number("/accelerated/fps_with_pipelining")};
    const double mj[2] = {1e3 * number("/baseline/modes/all/energy_j/mean"),
                          1e3 * number("/accelerated/modes/all/energy_j/mean")};
    rows += fmt::format("<tr><td>{}</td><td>{}</td>", p.point, html_escape(label));
    if (!run) {
      rows += fmt::format("<td colspan=\"4\">{}</td></tr>\n",
                          html_escape(p.error.empty() ? "no run" : "failed: " + p.error));
      continue;
    }
    rows += fmt::format("<td>{:.4g}</td><td>{:.4g}</td><td>{:.4g}</td><td>{:.4g}</td></tr>\n",
                        fps[0], fps[1], mj[0], mj[1]);
    // Data files quote text with double quotes (gnuplot's only quoting there).
    std::string quoted = label;
    std::replace(quoted.begin(), quoted.end(), '"', '\'');
    dat +=
        fmt::format("\"{}\" {:.9g} {:.9g} {:.9g} {:.9g}\n", quoted, fps[0], fps[1], mj[0], mj[1]);
    ++plotted;
  }
  std::string h = fmt::format(
      "<h4>Per workload point</h4>\n<p class=\"cap\">Each workload point was traced once (the "
      "real pipeline over the mix) and simulated on the platform; frame rate with FE/BE "
      "pipelining and mean energy per frame, CPU baseline against the accelerated platform.</p>\n");
  if (plot && plotted > 0) {
    const std::string stem = fmt::format("sweep{}_workloads", index);
    const std::string image = stem + kPlotExtension;
    const std::string data_file = gp_quote((dir / (stem + ".dat")).string());
    write_text(dir / (stem + ".dat"), dat);
    write_text(
        dir / (stem + ".gp"),
        cat(kTerminal, "set output ", gp_quote((dir / image).string()), "\n",
            "set multiplot layout 1,2 title ",
            gp_quote("Sweep " + sweep.sweep_id + ": frame rate and energy per workload point"),
            "\nset style data histograms\nset style histogram clustered gap 1",
            "\nset style fill solid 0.85 border -1\nset boxwidth 0.9\nset grid ytics",
            "\nset xtics rotate by -30\nset key top left\nset yrange [0:*]",
            "\nset ylabel 'Frames per second (FE/BE pipelined)'\nplot ", data_file,
            " using 2:xtic(1) title 'CPU baseline' lc rgb '#BBBBBB', '' using 3 title "
            "'accelerated' lc rgb '#0072B2'",
            "\nset ylabel 'Energy per frame (mJ)'\nplot ", data_file,
            " using 4:xtic(1) title 'CPU baseline' lc rgb '#BBBBBB', '' using 5 title "
            "'accelerated' lc rgb '#D55E00'\nunset multiplot\n"));
    run_gnuplot(gnuplot, dir / (stem + ".gp"), "sweep " + sweep.sweep_id + " workload plot");
    images.push_back(image);
    h += fmt::format("<img src=\"{}\" alt=\"frame rate and energy per workload point\">\n", image);
  }
  return h +
         "<table><tr><th>point</th><th>workload</th><th>baseline FPS</th><th>accelerated "
         "FPS</th><th>baseline mJ/frame</th><th>accelerated mJ/frame</th></tr>\n" +
         rows + "</table>\n";
}

std::string sweeps_html(const ResultsData& data, const fs::path& dir, const std::string& gnuplot,
                        bool plot, std::vector<std::string>& images) {
  std::string h = "<h2 id=\"sweeps\">Sweeps</h2>\n";
  if (data.sweeps.empty()) return h + "<p>The sweeps table is empty.</p>\n";
  int index = 0;
  for (const SweepData& sweep : data.sweeps) {
    ++index;
    std::vector<std::string> metrics;
    for (const SweepObjectiveInfo& o : sweep.objectives) metrics.push_back(o.metric);
    const auto label = [&](std::size_t i) {
      return fmt::format("{} ({})", sweep.objectives[i].metric,
                         sweep.objectives[i].maximize ? "maximize" : "minimize");
    };
    std::size_t pareto = 0, feasible = 0;
    for (const SweepPoint& p : sweep.points) {
      pareto += p.pareto ? 1 : 0;
      feasible += p.feasible ? 1 : 0;
    }
    h += fmt::format(
        "<h3>Sweep {} ({})</h3>\n<p class=\"cap\">{} points, {} meet the "
        "constraints, {} on the Pareto front of the objectives (as stored by edx "
        "sweep). Grey: infeasible; coloured: feasible, by the bottleneck of the point's "
        "accelerated latency (the resource holding its largest share, docs/MODEL.md "
        "\"Critical-path attribution\"); joined, larger: the Pareto front.</p>\n",
        html_escape(sweep.sweep_id), html_escape(sweep.spec), sweep.points.size(), feasible,
        pareto);
    for (std::size_t j = metrics.size() > 1 ? 1 : 0;
         plot && j < std::max<std::size_t>(metrics.size(), 1); ++j) {
      if (metrics.empty()) break;
      const bool single = metrics.size() == 1;
      // Blocks: 0 infeasible, 1 the Pareto front (sorted by x), then the feasible points of
      // each bottleneck ("" : not recorded).
      std::vector<std::string> bottlenecks;
      for (const SweepPoint& p : sweep.points) {
        if (p.feasible &&
            std::find(bottlenecks.begin(), bottlenecks.end(), p.bottleneck) == bottlenecks.end()) {
          bottlenecks.push_back(p.bottleneck);
        }
      }
      std::sort(bottlenecks.begin(), bottlenecks.end());
      std::vector<std::string> blocks(2 + bottlenecks.size());
      std::vector<std::pair<double, double>> front;
      for (const SweepPoint& p : sweep.points) {
        const auto x = single ? std::optional<double>(double(p.point)) : sweep_value(p, metrics[0]);
        const auto y = sweep_value(p, metrics[single ? 0 : j]);
        if (!x || !y) continue;
        const std::size_t block =
            p.feasible ? 2 + static_cast<std::size_t>(
                                 std::find(bottlenecks.begin(), bottlenecks.end(), p.bottleneck) -
                                 bottlenecks.begin())
                       : 0;
        blocks[block] += fmt::format("{:.9g} {:.9g}\n", *x, *y);
        if (p.pareto) front.emplace_back(*x, *y);
      }
      std::sort(front.begin(), front.end());
      for (const auto& [x, y] : front) blocks[1] += fmt::format("{:.9g} {:.9g}\n", x, y);
      std::string dat;
      for (const std::string& b : blocks)
        dat += "# block\n" + (b.empty() ? "nan nan\n" : b) + "\n\n";
      std::string feasible_plots;
      for (std::size_t b = 0; b < bottlenecks.size(); ++b) {
        feasible_plots += fmt::format(
            ", \\\n     '' index {} using 1:2 with points pt 7 ps 1 lc rgb '{}' title {}", 2 + b,
            kPalette[b % 8],
            gp_quote("bottleneck " +
                     (bottlenecks[b].empty() ? std::string("not recorded") : bottlenecks[b])));
      }
      const std::string stem = fmt::format("sweep{}_{}", index, j);
      const std::string png = stem + kPlotExtension;
      write_text(dir / (stem + ".dat"), dat);
      write_text(
          dir / (stem + ".gp"),
          cat(kTerminal, "set output ", gp_quote((dir / png).string()), "\n", "set title ",
              gp_quote("Sweep " + sweep.sweep_id + ": design points and Pareto front"),
              "\nset xlabel ", gp_quote(single ? std::string("Design point") : label(0)),
              "\nset ylabel ", gp_quote(label(single ? 0 : j)),
              "\nset offsets graph 0.05, graph 0.05, graph 0.05, graph 0.05",
              "\nset grid\nset key outside right top\n", "plot ",
              gp_quote((dir / (stem + ".dat")).string()),
              " index 0 using 1:2 with points pt 7 ps 1 lc rgb '#BBBBBB' title 'infeasible', "
              "'' index 1 using 1:2 with linespoints pt 6 ps 2 lw 1 lc rgb '#000000' title "
              "'Pareto front'",
              feasible_plots, "\n"));
      run_gnuplot(gnuplot, dir / (stem + ".gp"), "sweep " + sweep.sweep_id + " plot");
      images.push_back(png);
      h += fmt::format("<img src=\"{}\" alt=\"Pareto front\">\n", png);
    }
    h += accuracy_front_html(sweep, index, dir, gnuplot, plot, images);
    if (!sweep.generations.empty()) {
      h += convergence_html(sweep, index, dir, gnuplot, plot, images);
    }
    if (sweep.traces_workload) h += workload_html(data, sweep, index, dir, gnuplot, plot, images);
    h += fmt::format("<table><tr>{}<th>parameters</th>",
                     headings(results::sweep_points_table().spec, {"point", "run_id"}));
    std::vector<std::string> columns = metrics;
    for (const SweepPoint& p : sweep.points) {
      if (!p.metrics.is_object()) continue;
      for (const auto& [k, v] : p.metrics.items()) {
        if (std::find(columns.begin(), columns.end(), k) == columns.end()) columns.push_back(k);
      }
    }
    for (const std::string& c : columns) h += "<th>" + html_escape(c) + "</th>";
    h += headings(results::sweep_points_table().spec, {"feasible", "pareto"});
    h += "</tr>\n";
    for (const SweepPoint& p : sweep.points) {
      const std::string params = parameters_text(p);
      h += fmt::format("<tr><td>{}</td><td>{}</td><td>{}</td>", p.point, html_escape(p.run_id),
                       html_escape(params));
      for (const std::string& c : columns) {
        const auto v = sweep_value(p, c);
        h += "<td>" + (v ? fmt::format("{:.4g}", *v) : std::string("–")) + "</td>";
      }
      h += fmt::format("<td>{}</td><td>{}</td></tr>\n", p.feasible ? "yes" : "no",
                       p.pareto ? "yes" : "");
    }
    h += "</table>\n";
  }
  return h;
}

/// "edx_car × kitti.db": a run named for people (the hash stays as a small id).
std::string run_title(const RunData& r) {
  return fmt::format("{} × {}", r.platform, fs::path(r.trace).filename().string());
}

/// A number from the run summary at `path` (JSON pointer), NaN when absent.
double summary_number(const RunData& r, const std::string& path) {
  const nlohmann::json::json_pointer pointer(path);
  return r.summary.contains(pointer) && r.summary[pointer].is_number()
             ? r.summary[pointer].get<double>()
             : NAN;
}

/// A platform's runs of one workload over two or more seeds (table seed_runs, `edx simulate
/// --seeds --out`): each figure's samples.
struct SeedGroup {
  std::vector<std::size_t> runs;  ///< indices of data.runs, by seed
  std::vector<std::int64_t> seeds;
  nlohmann::json workload;
};

std::vector<SeedGroup> seed_groups(const ResultsData& data) {
  std::map<std::pair<std::string, std::string>, SeedGroup> groups;  // (config, workload)
  for (std::size_t i = 0; i < data.runs.size(); ++i) {
    const RunData& r = data.runs[i];
    if (r.seed_runs.empty()) continue;
    SeedGroup& g = groups[{r.config_hash, r.seed_runs.front().workload}];
    g.runs.push_back(i);
    g.seeds.push_back(r.seed_runs.front().seed);
    g.workload = r.seed_runs.front().workload_json;
  }
  std::vector<SeedGroup> out;
  for (const auto& entry : groups) {
    const SeedGroup& g = entry.second;
    if (g.runs.size() < 2) continue;
    std::vector<std::pair<std::int64_t, std::size_t>> by_seed;  // (seed, run)
    for (std::size_t k = 0; k < g.runs.size(); ++k) by_seed.emplace_back(g.seeds[k], g.runs[k]);
    std::sort(by_seed.begin(), by_seed.end());
    SeedGroup sorted{{}, {}, g.workload};
    for (const auto& [seed, run] : by_seed) {
      sorted.runs.push_back(run);
      sorted.seeds.push_back(seed);
    }
    out.push_back(std::move(sorted));
  }
  return out;
}

/// "edx_car × mix paper 1280x720, 400 frames (seeds 1, 2, 3)".
std::string group_title(const ResultsData& data, const SeedGroup& g) {
  std::string workload;
  for (const auto& [key, value] : g.workload.items()) {
    workload += fmt::format("{}{} {}", workload.empty() ? "" : ", ", key,
                            value.is_string() ? value.get<std::string>() : value.dump());
  }
  std::string seeds;
  for (std::int64_t seed : g.seeds) seeds += fmt::format("{}{}", seeds.empty() ? "" : ", ", seed);
  return fmt::format("{} × {} (seeds {})", data.runs[g.runs.front()].platform, workload, seeds);
}

/// One row of headline figures per run that has a section, then one per seed group with each
/// figure's mean and 95 % interval over its seeds: speedup per mode, SD reduction, FPS without /
/// with pipelining, energy, resources and fit.
std::string summary_html(const ResultsData& data, const std::vector<std::size_t>& sections,
                         const std::vector<SeedGroup>& groups) {
  std::string h =
      "<h2 id=\"summary\">Summary</h2>\n<p class=\"cap\">One row per platform run: accelerated "
      "against its CPU-only baseline; a run over seeds: each figure's mean [95 % interval, "
      "Student t]. Look for the e2e speedup per mode and whether the design fits its "
      "device.</p>\n<table><tr><th>run</th><th>e2e speedup per mode</th>"
      "<th>e2e SD reduction</th><th>FPS (baseline → accel.)</th><th>FPS pipelined (accel.)</th>"
      "<th>energy / frame (baseline → accel.)</th><th>LUT / DSP</th><th>fits</th></tr>\n";
  // A figure of one run (the summary's JSON pointer), or over a group's runs.
  using Figure = std::function<std::string(const std::string& pointer, int digits)>;
  const auto row = [&](const std::string& title, const RunData& r, const Figure& figure) {
    std::string speedups;
    if (r.summary.contains("comparison") && r.summary["comparison"].is_object()) {
      for (const auto& [mode, c] : r.summary["comparison"].items()) {
        speedups += fmt::format("{}{} {}×", speedups.empty() ? "" : "<br>", html_escape(mode),
                                figure("/comparison/" + mode + "/e2e_speedup", 2));
      }
    }
    const auto fits = nlohmann::json::json_pointer("/resources/fits");
    return fmt::format(
        "<tr><td>{}</td><td>{}</td><td>{}</td><td>{} → {}</td><td>{}</td><td>{} → {} J</td>"
        "<td>{} / {}</td><td>{}</td></tr>\n",
        title, speedups, figure("/comparison/all/e2e_sd_reduction", -1),
        figure("/baseline/fps_without_pipelining", 1),
        figure("/accelerated/fps_without_pipelining", 1),
        figure("/accelerated/fps_with_pipelining", 1),
        figure("/baseline/modes/all/energy_j/mean", 3),
        figure("/accelerated/modes/all/energy_j/mean", 3), figure("/resources/total/lut", 0),
        figure("/resources/total/dsp", 0),
        r.summary.contains(fits) ? (r.summary[fits].get<bool>() ? "yes" : "<b>no</b>") : "–");
  };
  const auto format = [](double v, int digits) { return digits < 0 ? pct(v) : num(v, digits); };
  for (std::size_t i : sections) {
    const RunData& r = data.runs[i];
    h += row(fmt::format("<a href=\"#run{}_\">{}</a> <small>{}</small>", i + 1,
                         html_escape(run_title(r)), html_escape(r.run_id)),
             r, [&](const std::string& pointer, int digits) {
               return format(summary_number(r, pointer), digits);
             });
  }
  for (const SeedGroup& g : groups) {
    std::vector<nlohmann::json> trees;
    for (std::size_t i : g.runs) trees.push_back({{"system", data.runs[i].summary}});
    std::map<std::string, Interval> figures;
    for (auto& [path, interval] : figures_over_runs(trees)) figures.emplace(path, interval);
    h += row(html_escape(group_title(data, g)), data.runs[g.runs.front()],
             [&](const std::string& pointer, int digits) {
               std::string path = "system" + pointer;
               std::replace(path.begin(), path.end(), '/', '.');
               const auto it = figures.find(path);
               if (it == figures.end()) return std::string("–");
               const Interval& i = it->second;
               return fmt::format("{} <small>[{}, {}]</small>", format(i.mean, digits),
                                  format(i.low, digits), format(i.high, digits));
             });
  }
  return h + "</table>\n";
}

/// The comparison with the paper's other baselines (its Table "Edx-Car speedup over
/// CPU/GPU/DSP"): one group of bars per compared baseline the check found, the paper's speedup
/// beside edx's (the check's `baselines.<name>.speedup` rows). Empty when there are none.
std::string baselines_chart_html(const CheckResult& check, const fs::path& dir, std::size_t n,
                                 const std::string& gnuplot, std::vector<std::string>& images) {
  std::string dat = "# label paper edx\n";
  int bars = 0;
  for (const CheckRow& row : check.rows) {
    const std::string& m = row.target.metric;
    if (!m.starts_with("baselines.") || !m.ends_with(".speedup") || !row.simulated) continue;
    std::string label = row.target.name;
    std::erase(label, '"');
    if (label.starts_with("speedup over ")) label.erase(0, 13);  // the chart's title says it
    dat += fmt::format("\"{}\" {:.6g} {:.6g}\n", label, row.target.paper, *row.simulated);
    ++bars;
  }
  if (bars == 0) return "";
  const std::string stem = fmt::format("baselines{}", n);
  const std::string image = stem + kPlotExtension;
  write_text(dir / (stem + ".dat"), dat);
  write_text(dir / (stem + ".gp"),
             cat(svg_terminal(960, 360), "set output ", gp_quote((dir / image).string()), "\n",
                 "datafile = ", gp_quote((dir / (stem + ".dat")).string()), "\n",
                 "set title 'Edx-Car speedup over each baseline: the paper and edx'\n",
                 "set ylabel 'speedup (x)'\nset style data histograms\n",
                 "set style histogram clustered gap 1\nset style fill solid 0.8 noborder\n",
                 "set boxwidth 0.9\nset yrange [0:*]\nset grid ytics\nset key top left\n",
                 "set xtics rotate by -20 scale 0\n",
                 "plot datafile using 2:xtic(1) title 'paper' lc rgb '#999999', \\\n",
                 "     '' using 3 title 'edx' lc rgb '#0072B2'\n"));
  run_gnuplot(gnuplot, dir / (stem + ".gp"), "baseline comparison plot");
  images.push_back(image);
  return fmt::format(
      "<p class=\"cap\">Edx-Car against the paper's other baselines (the platforms of "
      "<code>baselines:</code> in paper_targets.yaml, each run on the same trace): the paper's "
      "speedup beside edx's.</p>\n<img src=\"{}\" alt=\"baseline comparison\">\n",
      image);
}

/// The algorithm characterization (docs/CHARACTERIZATION.md) from its JSON: the paper's Sec. III
/// figure redrawn, one panel a scenario, ATE (log scale) against the CPU baseline's FPS: edx's
/// points (mean over the seeds, the SD as error bars) and the paper's (hollow circles where it
/// states a frame rate, hollow diamonds at edx's frame rate where it states only the error); then
/// the tables.
std::string characterization_html(const fs::path& file, const fs::path& dir,
                                  const std::string& gnuplot, bool plot,
                                  std::vector<std::string>& images) {
  nlohmann::json study;
  try {
    study = nlohmann::json::parse(read_input_file(file, "characterization file"));
    (void)study.at("points").items();
    (void)study.at("scenarios").items();
  } catch (const nlohmann::json::exception&) {
    throw std::runtime_error(
        fmt::format("{}: expected the characterization.json of edx characterize", file.string()));
  }
  const std::vector<std::string> scenarios = {"indoor_unknown", "indoor_known", "outdoor_unknown",
                                              "outdoor_known"};
  const auto number = [](const nlohmann::json& v) {
    return v.is_number() ? fmt::format("{:.6g}", v.get<double>()) : std::string("NaN");
  };
  std::string h = fmt::format(
      "<h2 id=\"characterization\">Algorithm characterization (paper Sec. III)</h2>\n<p "
      "class=\"cap\">Each backend on each scenario, {} frames a run at {}, seeds {}; frame rate on "
      "{}'s CPU-only baseline (<code>edx characterize</code>, docs/CHARACTERIZATION.md). Filled: "
      "edx (mean, SD over the seeds); hollow circles: the paper where it states a frame rate; "
      "hollow diamonds: the paper's error where it states only that, at edx's frame rate.</p>\n",
      study.value("frames", 0), html_escape(study.value("resolution", std::string())),
      html_escape(study.value("seeds", nlohmann::json::array()).dump()),
      html_escape(study.value("platform", std::string())));
  if (plot) {
    std::string script =
        svg_terminal(960, 720) + "set output " + gp_quote((dir / "characterization.svg").string()) +
        "\nset termoption noenhanced\nset multiplot layout 2,2\nset logscale y\nset grid\n"
        "set key top right font ',9'\n"
        "set xlabel 'FPS (CPU baseline)'\nset ylabel 'ATE RMSE (m)'\nset offsets graph 0.15, "
        "graph 0.15, graph 0.1, graph 0.1\n";
    for (const std::string& scenario : scenarios) {
      if (!study["points"].contains(scenario)) continue;
      std::string edx = "# backend fps ate sd\n", paper = "# backend fps ate fps_stated\n";
      for (const auto& [backend, p] : study["points"][scenario].items()) {
        edx += fmt::format("\"{}\" {} {} {}\n", backend, number(p["fps_mean"]),
                           number(p["ate_mean_m"]), number(p["ate_sd_m"]));
        if (!p["paper_ate_m"].is_number()) continue;
        // Where the paper states no frame rate, its error is drawn at edx's.
        const bool stated = p["paper_fps"].is_number();
        paper += fmt::format("\"{}\" {} {} {}\n", backend,
                             number(stated ? p["paper_fps"] : p["fps_mean"]),
                             number(p["paper_ate_m"]), stated ? 1 : 0);
      }
      const fs::path edx_dat = dir / fmt::format("characterization_{}.dat", scenario);
      const fs::path paper_dat = dir / fmt::format("characterization_{}_paper.dat", scenario);
      write_text(edx_dat, edx);
      write_text(paper_dat, paper);
      script += fmt::format(
          "set title '{}: {}'\nplot {} using 2:3:4 with yerrorbars pt 7 lc rgb '#0072B2' title "
          "'edx', "
          "'' using 2:3:1 with labels offset 1,1 font ',9' notitle, "
          "{} using 2:($4 == 1 ? $3 : 1/0) with points pt 6 ps 1.5 lc rgb '#D55E00' "
          "title 'paper', '' using 2:($4 == 0 ? $3 : 1/0) with points pt 12 ps 1.5 "
          "lc rgb '#D55E00' title 'paper (error only, at edx FPS)'\n",
          scenario, scenario.ends_with("unknown") ? "no map" : "with a map",
          gp_quote(edx_dat.string()), gp_quote(paper_dat.string()));
    }
    script += "unset multiplot\n";
    write_text(dir / "characterization.gp", script);
    run_gnuplot(gnuplot, dir / "characterization.gp", "characterization plot");
    images.push_back("characterization.svg");
    h += "<img src=\"characterization.svg\" alt=\"characterization\">\n";
  }
  h += "<table><tr><th>scenario</th><th>backend</th><th>ATE m (edx)</th><th>SD</th><th>paper</th>"
       "<th>FPS (edx)</th><th>paper</th></tr>\n";
  for (const std::string& scenario : scenarios) {
    if (!study["points"].contains(scenario)) continue;
    for (const auto& item : study["points"][scenario].items()) {
      const std::string& backend = item.key();
      const nlohmann::json& p = item.value();
      const auto cell = [&p](const char* key, int digits) {
        return p[key].is_number() ? num(p[key].get<double>(), digits) : std::string("–");
      };
      h += fmt::format(
          "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></"
          "tr>\n",
          scenario, html_escape(backend), cell("ate_mean_m", 3), cell("ate_sd_m", 3),
          cell("paper_ate_m", 2), cell("fps_mean", 2), cell("paper_fps", 1));
    }
  }
  h += "</table>\n<table><tr><th>scenario</th><th>least error (edx)</th><th>paper</th>"
       "<th>fastest (edx)</th><th>paper</th></tr>\n";
  for (const auto& item : study["scenarios"].items()) {
    const std::string& scenario = item.key();
    const nlohmann::json& r = item.value();
    const auto text = [&r](const char* key) {
      const std::string v = r.value(key, std::string());
      return v.empty() ? std::string("–") : html_escape(v);
    };
    h += fmt::format("<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
                     html_escape(scenario), text("least_error"), text("paper_least_error"),
                     text("fastest"), text("paper_fastest"));
  }
  return h + "</table>\n";
}

/// Whether the run's trace is the paper's scenario mix: the trace, read at the path the run
/// recorded, has meta sequence "mix:paper" (`edx trace --mix paper`, workloads/modes/mix_runner.cpp
/// mix_meta). False when the trace cannot be read there.
bool traces_paper_mix(const RunData& r) {
  try {
    const trace::TraceReader reader(r.trace);
    const auto sequence = reader.meta().find("sequence");
    return sequence != reader.meta().end() && sequence->second == "mix:paper";
  } catch (const std::exception&) {
    return false;
  }
}

/// The runs (indices of data.runs) whose paper check the report shows: the Edx-Car runs with a
/// section, the paper-mix run first (traces_paper_mix), then by the number of backend modes the
/// run has frames of (a mixed trace before a one-mode one, also when the trace is not readable),
/// then in database order.
std::vector<std::size_t> paper_check_runs(const ResultsData& data,
                                          const std::vector<std::size_t>& sections) {
  struct Key {
    bool paper_mix;
    std::size_t modes;
    std::size_t index;
  };
  std::vector<Key> keys;
  for (std::size_t i : sections) {
    const RunData& r = data.runs[i];
    if (!is_edx_car_run(r)) continue;
    const auto modes = modes_with_frames(nlohmann::json{{"system", r.summary}});
    keys.push_back({traces_paper_mix(r), modes ? modes->size() : 0, i});
  }
  std::stable_sort(keys.begin(), keys.end(), [](const Key& a, const Key& b) {
    return std::tie(b.paper_mix, b.modes) < std::tie(a.paper_mix, a.modes);
  });
  std::vector<std::size_t> order;
  for (const Key& k : keys) order.push_back(k.index);
  return order;
}

/// One paper check's section: a table and a plot of simulated / paper per target with the
/// tolerance band; over seeds, each figure's mean with its 95 % interval (error bars) and where
/// the interval lies against the band; n/a rows (modes the runs have no frames of) are listed,
/// not plotted. `id`: the section's anchor and plot stem; `command`: how to get it by hand.
std::string check_section(const CheckResult& check, const std::string& id, const std::string& title,
                          const std::string& command, const fs::path& dir,
                          const std::string& gnuplot, bool plot, std::vector<std::string>& images) {
  // Misses are explained in docs/MODEL.md: each target's own paragraph (its `explained`
  // anchor), else the section of all misses.
  const std::string model_file =
      "file://" +
      (default_targets_path().parent_path().parent_path() / "docs" / "MODEL.md").string();
  const std::string model_doc = model_file + "#what-is-not-reachable-honestly-and-why";
  const bool over_runs = check.runs > 1;
  const std::size_t not_applicable = check.count(Verdict::kNotApplicable);
  std::string h = fmt::format(
      "<h2 id=\"{0}\">Paper check: {1}</h2>\n<p class=\"cap\">{2} of {3} of the paper's Edx-Car "
      "figures within tolerance{4} (as <code>{5}</code>){6}. Why targets miss: <a "
      "href=\"{7}\">docs/MODEL.md</a>.</p>\n",
      id, title, check.passed(), check.counted(),
      over_runs ? fmt::format(" by their mean over {} seeds; each interval (95 %, Student t) "
                              "inside, across or outside the band",
                              check.runs)
                : "",
      html_escape(command),
      not_applicable == 0
          ? ""
          : fmt::format("; {} n/a: figures of modes without frames here", not_applicable),
      html_escape(model_doc));
  std::string dat = "# index ratio(simulated/paper) tolerance low high label\n";
  std::string rows = fmt::format(
      "<table><tr><th>target</th><th>paper</th><th>simulated{}</th><th>error</th>"
      "<th>tolerance</th><th>verdict</th>{}<th>source</th></tr>\n",
      over_runs ? " (mean [95 % interval])" : "", over_runs ? "<th>interval</th>" : "");
  int index = 0;
  for (const CheckRow& row : check.rows) {
    if (row.verdict == Verdict::kNotRun) continue;  // the characterization's: not in a DB
    const std::string verdict = to_string(row.verdict);
    const std::string unit = row.target.unit.empty() ? "" : " " + row.target.unit;
    const bool counted = row.verdict != Verdict::kNotApplicable;
    std::string simulated = "–";
    if (row.simulated) {
      simulated = row.interval
                      ? fmt::format("{:.4g} [{:.4g}, {:.4g}]{}", row.interval->mean,
                                    row.interval->low, row.interval->high, html_escape(unit))
                      : fmt::format("{:.4g}{}", *row.simulated, html_escape(unit));
    }
    rows += fmt::format(
        "<tr{}><td>{}</td><td>{:.4g}{}</td><td>{}</td><td>{}</td><td>±{:.0f}%</td><td>{}</td>{}"
        "<td>{}</td></tr>\n",
        row.verdict == Verdict::kPass || !counted ? "" : " class=\"miss\"",
        html_escape(row.target.name), row.target.paper, html_escape(unit), simulated,
        row.simulated ? fmt::format("{:+.1f}%", 100 * row.error) : "–", 100 * row.target.tolerance,
        row.verdict == Verdict::kPass ? verdict
        : !counted                    ? fmt::format("<span title=\"no {} frames here\">{}</span>",
                                                    html_escape(row.absent_mode), verdict)
                                      : fmt::format("<a href=\"{}\">{}</a>",
                                                    html_escape(row.target.explained.empty()
                                                                    ? model_doc
                                                                    : model_file + "#" + row.target.explained),
                                                    verdict),
        over_runs
            ? "<td>" + std::string(row.interval_verdict ? to_string(*row.interval_verdict) : "–") +
                  "</td>"
            : "",
        html_escape(row.target.source));
    if (!counted) continue;  // listed, not plotted
    if (row.simulated) {
      std::string label = row.target.name;
      std::erase(label, '"');
      const double paper = row.target.paper;
      const double low = row.interval ? row.interval->low : *row.simulated;
      const double high = row.interval ? row.interval->high : *row.simulated;
      dat += fmt::format("{} {:.6g} {:.6g} {:.6g} {:.6g} \"{}\"\n", index, *row.simulated / paper,
                         row.target.tolerance, std::min(low, high) / paper,
                         std::max(low, high) / paper, label);
    }
    ++index;
  }
  if (plot && index > 0) {
    const std::string image = id + kPlotExtension;
    write_text(dir / (id + ".dat"), dat);
    write_text(
        dir / (id + ".gp"),
        cat(svg_terminal(960, 200 + 18 * index), "set output ", gp_quote((dir / image).string()),
            "\n", "datafile = ", gp_quote((dir / (id + ".dat")).string()), "\n",
            "set title 'Simulated / paper per target (grey band: tolerance",
            (over_runs ? "; bars: 95 % interval over the seeds" : ""), ")'\n",
            "set xlabel 'simulated / paper'\nset logscale x\nset xrange [0.1:10]\n", "set yrange [",
            index, ":-1]\nset grid xtics\nset lmargin 38\nunset key\n", "set ytics scale 0\n",
            "clamp(x) = x < 0.1 ? 0.1 : (x > 10 ? 10 : x)\n",
            "plot datafile using (1-$3):1:(1-$3):(1+$3):($1-0.4):($1+0.4):ytic(6) "
            "with boxxyerror fs solid 0.3 noborder lc rgb '#BBBBBB', \\\n",
            (over_runs ? "     '' using (clamp($2)):1:(clamp($4)):(clamp($5)) with xerrorbars "
                         "pt -1 lc rgb '#555555', \\\n"
                       : ""),
            "     '' using (clamp($2)):1:(abs($2-1) <= $3 ? 0x009E73 : 0xD55E00) with points pt 7 "
            "ps 1.2 lc rgb variable\n"));
    run_gnuplot(gnuplot, dir / (id + ".gp"), "paper check plot");
    images.push_back(image);
    h += fmt::format(
        "<p class=\"cap\">Green: within tolerance; orange: a miss (clamped to 0.1–10 on the "
        "log axis). Look for dots outside the grey band.</p>\n<img src=\"{}\" alt=\"paper "
        "check\">\n",
        image);
  }
  return h + rows + "</table>\n";
}

/// The paper checks (reports/paper_targets.yaml, as `edx check`): first each Edx-Car seed group
/// over its seeds (a paper-mix workload first), then each Edx-Car run with a section in
/// paper_check_runs' order.
std::string paper_check_html(const ResultsData& data, const std::vector<std::size_t>& sections,
                             const std::vector<SeedGroup>& groups, const fs::path& dir,
                             const std::string& gnuplot, bool plot,
                             std::vector<std::string>& images) {
  const std::vector<PaperTarget> targets = load_targets(default_targets_path());
  const std::vector<ComparedBaseline> baselines = load_baselines(default_targets_path());
  const auto metrics_of = [&](const RunData& r) {
    nlohmann::json metrics = run_metrics(r);
    add_baseline_metrics(metrics, data, r, baselines);  // the runs of the compared platforms
    return metrics;
  };
  std::vector<const SeedGroup*> car_groups;
  for (const SeedGroup& g : groups) {
    if (is_edx_car_run(data.runs[g.runs.front()])) car_groups.push_back(&g);
  }
  std::stable_partition(car_groups.begin(), car_groups.end(), [](const SeedGroup* g) {
    return g->workload.value("mix", std::string()) == "paper";
  });
  std::string h;
  for (std::size_t k = 0; k < car_groups.size(); ++k) {
    const SeedGroup& g = *car_groups[k];
    std::vector<nlohmann::json> trees;
    std::vector<std::string> ids;
    for (std::size_t i : g.runs) {
      trees.push_back(metrics_of(data.runs[i]));
      ids.push_back(data.runs[i].run_id);
    }
    h += check_section(check_targets_over_runs(targets, trees, ids),
                       fmt::format("check_seeds{}", k + 1), html_escape(group_title(data, g)),
                       "edx check --config CONFIG --workload W --seeds S --trace-store DIR", dir,
                       gnuplot, plot, images);
  }
  for (std::size_t i : paper_check_runs(data, sections)) {
    const RunData& r = data.runs[i];
    const CheckResult check = check_targets(targets, metrics_of(r), r.run_id);
    h += check_section(
        check, fmt::format("check{}", i + 1),
        fmt::format("{} <small>{}</small>", html_escape(run_title(r)), html_escape(r.run_id)),
        "edx check --results DB --run " + r.run_id, dir, gnuplot, plot, images);
    if (plot) h += baselines_chart_html(check, dir, i + 1, gnuplot, images);
  }
  return h;
}

/// A table cell: values longer than a line fold into details/summary.
std::string folded_cell(const std::string& value) {
  constexpr std::size_t kShown = 80;
  if (value.size() <= kShown) return "<td class=\"text\">" + html_escape(value) + "</td>";
  return fmt::format(
      "<td class=\"text\"><details><summary>{}…</summary><code>{}</code></details></td>",
      html_escape(value.substr(0, kShown)), html_escape(value));
}

/// The runs: those with a section first, named platform × trace; the points of each sweep
/// folded under it.
std::string runs_table_html(const ResultsData& data, const std::vector<std::size_t>& sections,
                            const std::map<std::string, std::string>& sweep_of_run) {
  const std::string header =
      fmt::format("<table><tr><th>run</th>{}</tr>\n",
                  headings(results::runs_table().spec, {"run_id", "frames", "policy"}));
  const auto row = [&](const RunData& r, const std::string& name) {
    return fmt::format("<tr><td>{}</td><td><small>{}</small></td><td>{}</td><td>{}</td></tr>\n",
                       name, html_escape(r.run_id), r.frames, html_escape(r.policy));
  };
  std::string h = "<h2>Runs</h2>\n" + header;
  for (std::size_t i : sections) {
    h += row(data.runs[i], fmt::format("<a href=\"#run{}_\">{}</a>", i + 1,
                                       html_escape(run_title(data.runs[i]))));
  }
  h += "</table>\n";
  for (const SweepData& sweep : data.sweeps) {
    std::string rows;
    for (const SweepPoint& p : sweep.points) {
      const auto run = std::find_if(data.runs.begin(), data.runs.end(),
                                    [&](const RunData& r) { return r.run_id == p.run_id; });
      if (run == data.runs.end() || !sweep_of_run.contains(run->run_id) ||
          std::find(sections.begin(), sections.end(), std::size_t(run - data.runs.begin())) !=
              sections.end()) {
        continue;
      }
      rows += row(*run, fmt::format("{}, {} (point of sweep <a href=\"#sweeps\">{}</a>)",
                                    html_escape(run_title(*run)), html_escape(parameters_text(p)),
                                    html_escape(sweep.sweep_id)));
    }
    if (rows.empty()) continue;
    h +=
        fmt::format("<details><summary>Sweep {}: {} point runs</summary>\n{}{}</table></details>\n",
                    html_escape(sweep.sweep_id), sweep.points.size(), header, rows);
  }
  return h;
}

/// The trace's meta table; long values (pipeline_params) fold.
std::string trace_meta_html(const fs::path& trace_path) {
  const trace::TraceReader reader(trace_path);
  std::string h = fmt::format("<h2>Trace {}</h2>\n<table><tr><th>key</th><th>value</th></tr>\n",
                              html_escape(trace_path.string()));
  for (const auto& [k, v] : reader.meta()) {
    h += fmt::format("<tr><td>{}</td>{}</tr>\n", html_escape(k), folded_cell(v));
  }
  return h + "</table>\n";
}

constexpr const char* kStyle = R"css(
body { font-family: sans-serif; max-width: 1100px; margin: 2em auto; color: #222; }
table { border-collapse: collapse; margin: 0.5em 0 1.5em; font-size: 0.9em; }
th, td { border: 1px solid #ccc; padding: 3px 8px; text-align: right; }
th { background: #f0f0f0; } td:first-child, th:first-child { text-align: left; }
td.text { text-align: left; } td.text code { white-space: normal; }
/* a table wider than the page wraps its long words (run ids, ate_rmse_vio_reference) */
th, td { overflow-wrap: anywhere; }
tr.miss td { background: #fdebe3; } small { color: #777; }
h2 small { font-weight: normal; }
tr.total td { font-weight: bold; }
img { max-width: 100%; border: 1px solid #eee; }
p.cap { color: #555; font-size: 0.9em; }
)css";

/// Test-only self-check, inert unless the page is opened as index.html?browser-check (the
/// browser test, docs/REPORTS.md): after load, appends <pre id="browser-check"> with JSON
/// {images, broken: [src], wide: [tag#id], scroll_width, viewport}.
constexpr const char* kBrowserCheck = R"js(
if (location.search.includes('browser-check')) addEventListener('load', () => {
  const viewport = document.documentElement.clientWidth;
  const images = [...document.images];
  const broken = images.filter(i => !i.complete || i.naturalWidth === 0).map(i => i.src);
  const wide = [...document.body.querySelectorAll('*')]
      .filter(e => e.getBoundingClientRect().right > viewport + 0.5)
      .map(e => e.tagName + (e.id ? '#' + e.id : ''));
  const out = document.createElement('pre');
  out.id = 'browser-check';
  out.textContent = JSON.stringify({images: images.length, broken, wide, viewport,
                                    scroll_width: document.documentElement.scrollWidth});
  document.body.appendChild(out);
});
)js";

}  // namespace

bool gnuplot_available(const std::string& gnuplot) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
  std::string version = "--version";
  std::vector<char*> argv = {const_cast<char*>(gnuplot.c_str()), version.data(), nullptr};
  pid_t pid = 0;
  const int rc = posix_spawnp(&pid, gnuplot.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) return false;
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

ReportResult write_report(const ResultsData& data, const ReportOptions& options) {
  const fs::path out = fs::absolute(options.out_dir).lexically_normal();
  if (fs::exists(out) && !fs::is_directory(out)) {
    throw std::runtime_error(fmt::format("{}: exists and is not a directory", out.string()));
  }
  const fs::path parent = out.parent_path();
  std::error_code error;
  fs::create_directories(parent, error);
  if (error) {
    throw std::runtime_error(fmt::format("{}: cannot create its folder {} ({})", out.string(),
                                         parent.string(), error.message()));
  }
  const fs::path stage = parent / fmt::format(".{}.tmp-{}", out.filename().string(), ::getpid());
  fs::remove_all(stage);
  fs::create_directories(stage);
  ReportResult result;
  try {
    result.plotted = gnuplot_available(options.gnuplot);
    std::string body;
    if (!result.plotted) {
      body += fmt::format("<p><b>Plots skipped: {} was not found.</b></p>\n",
                          html_escape(options.gnuplot));
    }
    // A run that only a sweep wrote (no per-frame rows) is a row of its sweep's table, not a
    // section of its own: a sweep of hundreds of points would otherwise bury the runs an
    // architect simulated by hand.
    std::map<std::string, std::string> sweep_of_run;
    for (const SweepData& sweep : data.sweeps) {
      for (const SweepPoint& p : sweep.points) sweep_of_run.emplace(p.run_id, sweep.sweep_id);
    }
    // A run of a seed group is a sample of the group's figures (the summary's and the check's
    // intervals), not a section of its own.
    const std::vector<SeedGroup> groups = seed_groups(data);
    std::set<std::size_t> grouped;
    for (const SeedGroup& g : groups) grouped.insert(g.runs.begin(), g.runs.end());
    const auto has_section = [&](const RunData& r) {
      return !grouped.contains(static_cast<std::size_t>(&r - data.runs.data())) &&
             (!r.frame_rows.empty() || !sweep_of_run.contains(r.run_id));
    };
    std::vector<std::size_t> sections;
    for (std::size_t i = 0; i < data.runs.size(); ++i) {
      if (has_section(data.runs[i])) sections.push_back(i);
    }
    body += summary_html(data, sections, groups);
    body += paper_check_html(data, sections, groups, stage, options.gnuplot, result.plotted,
                             result.images);
    body += runs_table_html(data, sections, sweep_of_run);
    if (!options.trace.empty()) body += trace_meta_html(options.trace);
    if (!options.characterization.empty()) {
      body += characterization_html(options.characterization, stage, options.gnuplot,
                                    result.plotted, result.images);
    }
    for (std::size_t i : sections) {
      RunReport run(data.runs[i], i, stage, options.gnuplot, result.plotted);
      body += run.html(result.images);
    }
    if (data.has_sweeps)
      body += sweeps_html(data, stage, options.gnuplot, result.plotted, result.images);
    const std::string html = fmt::format(
        "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>edx report: {0}</title>"
        "<style>{1}</style><script>{5}</script></head>\n<body>\n<h1>edx report</h1>\n<p>Results "
        "database: "
        "<code>{0}</code> ({2} run{3}). Generated by <code>edx report</code>; plots by "
        "gnuplot (scripts and data beside them: *.gp, *.dat).</p>\n{4}</body></html>\n",
        html_escape(data.path.string()), kStyle, data.runs.size(), data.runs.size() == 1 ? "" : "s",
        body, kBrowserCheck);
    common::write_file_atomically(stage / "index.html", html);
    // Swap the finished directory into place.
    const fs::path old = parent / fmt::format(".{}.old-{}", out.filename().string(), ::getpid());
    const bool existed = fs::exists(out);
    if (existed) fs::rename(out, old);
    fs::rename(stage, out);
    if (existed) fs::remove_all(old);
  } catch (const std::exception& e) {
    std::error_code ignored;
    fs::remove_all(stage, ignored);
    throw std::runtime_error(fmt::format("{}: report not written: {}", out.string(), e.what()));
  }
  result.index = out / "index.html";
  return result;
}

}  // namespace edx::reports
