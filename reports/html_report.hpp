#pragma once
// `edx report`: an HTML page (DIR/index.html) of a results database with gnuplot plots and tables
// of every summary figure (docs/REPORTS.md lists each plot). Written into a temporary directory
// beside DIR and renamed into place, so DIR is never half-written.
#include <filesystem>
#include <string>
#include <vector>

#include "reports/results_reader.hpp"

namespace edx::reports {

struct ReportOptions {
  std::filesystem::path out_dir;
  std::filesystem::path trace;  ///< optional: a trace database whose meta table is shown
  /// Optional: characterization.json of `edx characterize`, drawn as the paper's Sec. III
  /// figure (error against frame rate per scenario) with edx's points beside the paper's.
  std::filesystem::path characterization;
  std::string gnuplot = "gnuplot";  ///< executable, looked up on PATH
};

struct ReportResult {
  std::filesystem::path index;      ///< out_dir/index.html
  std::vector<std::string> images;  ///< file names of the plots inside out_dir
  bool plotted = false;             ///< false: gnuplot was not found, tables only
};

/// True when `gnuplot` can be run (`gnuplot --version` exits 0).
bool gnuplot_available(const std::string& gnuplot = "gnuplot");

/// Writes the report of `data`. Errors: std::runtime_error (a failed gnuplot script names the
/// plot and gnuplot's first error line); DIR is then left as it was.
ReportResult write_report(const ResultsData& data, const ReportOptions& options);

}  // namespace edx::reports
