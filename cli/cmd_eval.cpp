// `edx eval`: trajectory error (ATE, RPE, KITTI segment errors) of an estimate file against
// ground truth. Parses arguments, calls edx::eval::evaluate and prints a table or JSON.
#include <fmt/core.h>
#include <spdlog/spdlog.h>

#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "cli/commands.hpp"
#include "workloads/eval/evaluate.hpp"
#include "workloads/eval/trajectory_io.hpp"

namespace edx::cli {
namespace {

struct EvalArguments {
  std::string gt_path;
  std::string est_path;
  std::string format;
  std::string alignment;
  double t_max_diff_s = 0.02;
  double rpe_delta_m = 100.0;
  bool json = false;
  bool kitti_odom_eval = false;
};

/// A figure that exists only when it was measured over at least one pair or segment.
nlohmann::ordered_json figure_or_null(std::size_t count, double value) {
  return count > 0 ? nlohmann::ordered_json(value) : nlohmann::ordered_json(nullptr);
}

nlohmann::ordered_json to_json(const EvalArguments& args, const eval::EvalResult& r) {
  nlohmann::ordered_json json;
  json["gt"] = args.gt_path;
  json["est"] = args.est_path;
  json["format"] = args.format;
  json["alignment"] = eval::alignment_method_name(r.alignment);
  json["conventions"] = r.kitti_odom_eval ? "kitti-odom-eval" : "edx";
  json["gt_poses"] = r.gt_poses;
  json["est_poses"] = r.est_poses;
  json["pairs"] = r.pairs;
  json["est_unmatched"] = r.est_unmatched;
  json["align_scale"] = r.align.scale;
  json["align_rotation"] = nlohmann::ordered_json::array();
  for (int row = 0; row < 3; ++row) {
    json["align_rotation"].push_back(
        {r.align.rotation(row, 0), r.align.rotation(row, 1), r.align.rotation(row, 2)});
  }
  json["align_translation_m"] = {r.align.translation.x(), r.align.translation.y(),
                                 r.align.translation.z()};
  json["gt_length_m"] = r.gt_length_m;
  json["ate_rmse_m"] = r.ate_m.rmse;
  json["ate_mean_m"] = r.ate_m.mean;
  json["ate_median_m"] = r.ate_m.median;
  json["ate_max_m"] = r.ate_m.max;
  json["rpe_pairs"] = r.rpe_trans_m.count;
  json["rpe_trans_m"] = figure_or_null(r.rpe_trans_m.count, r.rpe_trans_m.mean);
  json["rpe_rot_deg"] = figure_or_null(r.rpe_rot_deg.count, r.rpe_rot_deg.mean);
  json["rpe_trans_rmse_m"] = figure_or_null(r.rpe_trans_m.count, r.rpe_trans_m.rmse);
  json["rpe_rot_rmse_deg"] = figure_or_null(r.rpe_rot_deg.count, r.rpe_rot_deg.rmse);
  json["rpe_delta_m"] = r.rpe_delta_m;
  json["rpe_delta_pairs"] = r.rpe_delta_trans_m.count;
  json["rpe_delta_trans_m"] = figure_or_null(r.rpe_delta_trans_m.count, r.rpe_delta_trans_m.mean);
  json["rpe_delta_rot_deg"] = figure_or_null(r.rpe_delta_rot_deg.count, r.rpe_delta_rot_deg.mean);
  json["kitti_segments"] = r.kitti.segments;
  json["kitti_t_err_pct"] = r.kitti.t_err_pct ? nlohmann::ordered_json(*r.kitti.t_err_pct)
                                              : nlohmann::ordered_json(nullptr);
  json["kitti_r_err_deg_per_100m"] = r.kitti.r_err_deg_per_100m
                                         ? nlohmann::ordered_json(*r.kitti.r_err_deg_per_100m)
                                         : nlohmann::ordered_json(nullptr);
  json["kitti_by_length"] = nlohmann::ordered_json::array();
  for (const auto& length : r.kitti.by_length) {
    json["kitti_by_length"].push_back({{"length_m", length.length_m},
                                       {"segments", length.segments},
                                       {"t_err_pct", length.t_err_pct},
                                       {"r_err_deg_per_100m", length.r_err_deg_per_100m}});
  }
  return json;
}

std::string figure_text(std::size_t count, double value, const char* unit) {
  return count > 0 ? fmt::format("{:.6g} {}", value, unit) : std::string("n/a");
}

void print_table(const EvalArguments& args, const eval::EvalResult& r) {
  fmt::print("edx eval: {} against {} ({}, {} alignment, {} conventions)\n", args.est_path,
             args.gt_path, args.format, eval::alignment_method_name(r.alignment),
             r.kitti_odom_eval ? "kitti-odom-eval" : "edx");
  const auto row = [](const std::string& name, const std::string& value,
                      const std::string& note = {}) {
    if (note.empty()) {
      fmt::print("  {:<32} {}\n", name, value);
    } else {
      fmt::print("  {:<32} {:<20} {}\n", name, value, note);
    }
  };
  row("pose pairs", fmt::format("{}", r.pairs),
      fmt::format("est {}, gt {}, est without gt {}", r.est_poses, r.gt_poses, r.est_unmatched));
  row("ground-truth length", fmt::format("{:.6g} m", r.gt_length_m));
  row("alignment scale", fmt::format("{:.6g}", r.align.scale));
  row("ATE RMSE", fmt::format("{:.6g} m", r.ate_m.rmse),
      fmt::format("mean {:.4g}, median {:.4g}, max {:.4g} m", r.ate_m.mean, r.ate_m.median,
                  r.ate_m.max));
  row("RPE consecutive, translation", figure_text(r.rpe_trans_m.count, r.rpe_trans_m.mean, "m"),
      fmt::format("mean over {} pairs (rmse {:.4g} m)", r.rpe_trans_m.count, r.rpe_trans_m.rmse));
  row("RPE consecutive, rotation", figure_text(r.rpe_rot_deg.count, r.rpe_rot_deg.mean, "deg"),
      fmt::format("mean (rmse {:.4g} deg)", r.rpe_rot_deg.rmse));
  row(fmt::format("RPE over {:g} m, translation", r.rpe_delta_m),
      figure_text(r.rpe_delta_trans_m.count, r.rpe_delta_trans_m.mean, "m"),
      fmt::format("mean over {} pairs", r.rpe_delta_trans_m.count));
  row(fmt::format("RPE over {:g} m, rotation", r.rpe_delta_m),
      figure_text(r.rpe_delta_rot_deg.count, r.rpe_delta_rot_deg.mean, "deg"), "mean");
  row("KITTI translational error",
      figure_text(r.kitti.segments, r.kitti.t_err_pct.value_or(0.0), "%"),
      fmt::format("mean over {} segments", r.kitti.segments));
  row("KITTI rotational error",
      figure_text(r.kitti.segments, r.kitti.r_err_deg_per_100m.value_or(0.0), "deg/100 m"));
  if (!r.kitti.by_length.empty()) {
    fmt::print("  {:>8} {:>9} {:>10} {:>16}\n", "length", "segments", "t_err %", "r_err deg/100m");
    for (const auto& length : r.kitti.by_length) {
      fmt::print("  {:>6g} m {:>9} {:>10.4f} {:>16.4f}\n", length.length_m, length.segments,
                 length.t_err_pct, length.r_err_deg_per_100m);
    }
  }
}

void run_eval(const EvalArguments& args, const CLI::App& command) {
  const eval::TrajectoryFormat format = eval::parse_trajectory_format(args.format);
  if (format == eval::TrajectoryFormat::kKitti && command.count("--t-max-diff") > 0) {
    throw CLI::ValidationError("--t-max-diff", "applies to the tum and euroc formats only");
  }
  if (args.kitti_odom_eval && format != eval::TrajectoryFormat::kKitti) {
    throw CLI::ValidationError("--kitti-odom-eval", "needs --format kitti");
  }
  eval::EvalOptions options;
  options.alignment = eval::parse_alignment_method(args.alignment);
  options.t_max_diff_s = args.t_max_diff_s;
  options.rpe_delta_m = args.rpe_delta_m;
  options.kitti_odom_eval = args.kitti_odom_eval;

  const eval::Trajectory gt = eval::read_trajectory(args.gt_path, format);
  const eval::Trajectory est = eval::read_trajectory(args.est_path, format);
  for (const eval::Trajectory* t : {&gt, &est}) {
    if (t->repeated_stamps_dropped > 0) {
      spdlog::warn("{}:{}: {} pose(s) repeat the previous pose's stamp; the first of each kept",
                   t->source, t->first_repeated_line, t->repeated_stamps_dropped);
    }
  }
  const eval::EvalResult result = eval::evaluate(gt, est, options);
  if (args.json) {
    fmt::print("{}\n", to_json(args, result).dump(2));
  } else {
    print_table(args, result);
  }
}

}  // namespace

void add_eval_command(CLI::App& app) {
  auto args = std::make_shared<EvalArguments>();
  CLI::App* command = app.add_subcommand(
      "eval",
      "Trajectory error of an estimate against ground truth: ATE RMSE after alignment, RPE over "
      "consecutive pairs and over a distance, KITTI segment errors (100..800 m). See "
      "docs/EVAL.md.");
  command->add_option("--gt", args->gt_path, "ground-truth trajectory file")->required();
  command->add_option("--est", args->est_path, "estimated trajectory file")->required();
  command
      ->add_option("--format", args->format,
                   "file format: kitti (12 numbers [R|t] a line, optionally led by a frame "
                   "index), tum (t x y z qx qy qz qw), euroc (CSV t_ns,p,q_wxyz)")
      ->required()
      ->check(CLI::IsMember({"kitti", "tum", "euroc"}));
  command
      ->add_option("--align", args->alignment,
                   "alignment of the estimate: none, se3 (Umeyama), sim3 (Umeyama with scale), "
                   "posyaw (position + yaw about z)")
      ->required()
      ->check(CLI::IsMember({"none", "se3", "sim3", "posyaw"}));
  command
      ->add_option("--t-max-diff", args->t_max_diff_s,
                   "largest timestamp difference (s) of an associated pair (tum, euroc)")
      ->capture_default_str()
      ->check(non_negative_number());
  command
      ->add_option("--rpe-delta-m", args->rpe_delta_m,
                   "ground-truth path length (m) between the two poses of the distance RPE")
      ->capture_default_str()
      ->check(positive_number());
  command->add_flag("--json", args->json, "print the figures as one JSON object");
  command->add_flag("--kitti-odom-eval", args->kitti_odom_eval,
                    "use the conventions of the public kitti-odom-eval tool (eval_odom.py): "
                    "poses relative to the first estimated frame, segments along the whole ground "
                    "truth (kitti format only)");
  command->callback([args, command] { run_eval(*args, *command); });
}

}  // namespace edx::cli
