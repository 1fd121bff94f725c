// `edx vocab`: trains a bag-of-words vocabulary of ORB descriptors on datasets (the real
// frontend on every n-th frame) and saves it (docs/BOW.md). Logic:
// workloads/backend/registration/bow.
#include <fmt/core.h>

#include <filesystem>
#include <string>
#include <vector>

#include "cli/commands.hpp"
#include "cli/progress.hpp"
#include "workloads/backend/registration/bow/training.hpp"

namespace edx::cli {
namespace {

struct VocabArguments {
  std::vector<std::string> datasets;
  std::string out;
  std::string resolution;
  int stride = bow::TrainingOptions{}.frame_stride;
  std::size_t max_descriptors = bow::TrainingOptions{}.max_descriptors;
  int branching = bow::VocabularyOptions{}.branching;
  int depth = bow::VocabularyOptions{}.depth;
  std::uint64_t seed = bow::VocabularyOptions{}.seed;
  bool force = false;
  bool json = false;
};

/// "PATH" (EuRoC layout) or "kitti:PATH" / "euroc:PATH".
bow::TrainingDataset parse_dataset(const std::string& text, const std::string& resolution) {
  bow::TrainingDataset d;
  std::string path = text;
  for (const char* format : {"euroc", "kitti"}) {
    const std::string prefix = std::string(format) + ":";
    if (text.starts_with(prefix)) {
      d.format = datasets::parse_dataset_format(format);
      path = text.substr(prefix.size());
    }
  }
  d.path = path;
  if (!resolution.empty()) d.options.resize = datasets::parse_resolution(resolution);
  return d;
}

void run(const VocabArguments& args) {
  if (std::filesystem::exists(args.out) && !args.force) {
    throw std::runtime_error(
        fmt::format("{}: output exists (refusing to overwrite; use --force)", args.out));
  }
  bow::TrainingOptions options;
  for (const std::string& d : args.datasets)
    options.datasets.push_back(parse_dataset(d, args.resolution));
  options.frame_stride = args.stride;
  options.max_descriptors = args.max_descriptors;
  options.vocabulary.branching = args.branching;
  options.vocabulary.depth = args.depth;
  options.vocabulary.seed = args.seed;
  ProgressBar bar("vocab");
  const bow::TrainedVocabulary trained = bow::train_vocabulary(
      options, [&bar](std::string_view stage, std::size_t done, std::size_t total) {
        bar.update(done, total, "steps", stage);
      });
  trained.vocabulary.save(args.out);
  if (args.json) {
    fmt::print("{}\n",
               nlohmann::json{{"out", args.out}, {"summary", trained.summary.to_json()}}.dump(2));
  } else {
    const bow::TrainingSummary& s = trained.summary;
    fmt::print(
        "vocabulary {}\ntrained on {} images ({} descriptors, {} clustered) from {} datasets\n"
        "tree       {} nodes, {} words ({} unseen), k = {}, L = {}\n"
        "time       features {:.1f} s, clustering {:.1f} s, idf {:.1f} s\n",
        args.out, s.images, s.descriptors, s.descriptors_clustered, s.datasets, s.nodes, s.words,
        s.words_unseen, args.branching, args.depth, s.feature_seconds, s.clustering_seconds,
        s.idf_seconds);
  }
}

}  // namespace

void add_vocab_command(CLI::App& app) {
  auto args = std::make_shared<VocabArguments>();
  CLI::App* cmd = app.add_subcommand(
      "vocab", "Train a bag-of-words vocabulary of ORB descriptors on datasets (docs/BOW.md)");
  cmd->add_option("--datasets", args->datasets,
                  "Datasets to train on: PATH (EuRoC layout, e.g. a synthetic DIR/map) or "
                  "kitti:PATH (a KITTI sequence folder)")
      ->required();
  cmd->add_option("--out", args->out, "Vocabulary file to write")->required();
  cmd->add_option("--stride", args->stride, "Use every N-th frame")->check(positive_number());
  cmd->add_option("--max-descriptors", args->max_descriptors,
                  "Cluster at most this many descriptors (a seeded sample; 0: all)");
  cmd->add_option("--branching", args->branching, "k: children per node")->check(CLI::Range(2, 64));
  cmd->add_option("--depth", args->depth, "L: levels of the tree")->check(CLI::Range(1, 16));
  cmd->add_option("--seed", args->seed, "Seed of the clustering");
  cmd->add_option("--resolution", args->resolution, "Resize the frames to WxH first");
  cmd->add_flag("--force", args->force, "Overwrite an existing output file");
  cmd->add_flag("--json", args->json, "Print the summary as JSON (only JSON on stdout)");
  cmd->callback([args] { run(*args); });
}

}  // namespace edx::cli
