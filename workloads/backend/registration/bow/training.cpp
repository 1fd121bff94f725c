#include "workloads/backend/registration/bow/training.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <iterator>
#include <numeric>
#include <stdexcept>

#include "workloads/datasets/synthetic/random.hpp"
#include "workloads/frontend/stereo_frontend.hpp"

namespace edx::bow {
namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

void TrainingOptions::validate() const {
  if (datasets.empty()) throw std::runtime_error("vocabulary training: no datasets given");
  for (std::size_t i = 0; i < datasets.size(); ++i) {
    if (datasets[i].path.empty()) {
      throw std::runtime_error(fmt::format("vocabulary training: datasets[{}] has no path", i));
    }
  }
  if (frame_stride < 1) {
    throw std::runtime_error(
        fmt::format("vocabulary training: frame_stride = {}, expected >= 1", frame_stride));
  }
  vocabulary.validate();
  frontend.validate();
}

nlohmann::json TrainingOptions::to_json() const {
  nlohmann::json sets = nlohmann::json::array();
  for (const TrainingDataset& d : datasets) {
    nlohmann::json j = {{"path", d.path.string()}, {"format", datasets::to_string(d.format)}};
    if (d.options.resize) {
      j["resize"] = fmt::format("{}x{}", d.options.resize->width, d.options.resize->height);
    }
    if (!d.options.kitti_sequence.empty()) j["kitti_sequence"] = d.options.kitti_sequence;
    sets.push_back(std::move(j));
  }
  return {{"datasets", std::move(sets)},
          {"frame_stride", frame_stride},
          {"max_descriptors", max_descriptors},
          {"vocabulary", vocabulary.to_json()},
          {"frontend", frontend::to_json(frontend)}};
}

nlohmann::json TrainingSummary::to_json() const {
  return {{"datasets", datasets},
          {"images", images},
          {"descriptors", descriptors},
          {"descriptors_clustered", descriptors_clustered},
          {"nodes", nodes},
          {"words", words},
          {"words_unseen", words_unseen},
          {"clustering",
           {{"node_splits", clustering.node_splits},
            {"iterations", clustering.iterations},
            {"hamming_distances", clustering.distances}}},
          {"feature_seconds", feature_seconds},
          {"clustering_seconds", clustering_seconds},
          {"idf_seconds", idf_seconds}};
}

std::vector<std::vector<Descriptor>> sample_left_descriptors(
    const datasets::Dataset& dataset, int stride, const frontend::FrontendOptions& options,
    std::vector<std::size_t>* frame_indices, const TrainingProgress& progress) {
  if (stride < 1) throw std::runtime_error(fmt::format("frame stride {}, expected >= 1", stride));
  const datasets::StereoCalibration& calibration = dataset.calibration();
  frontend::StereoFrontend frontend(options, {calibration.rectified.fx, calibration.baseline_m});
  std::vector<std::vector<Descriptor>> images;
  if (frame_indices) frame_indices->clear();
  const std::size_t total = (dataset.frame_count() + stride - 1) / static_cast<std::size_t>(stride);
  for (std::size_t index = 0; index < dataset.frame_count(); index += stride) {
    const datasets::StereoFrame frame = dataset.load_frame(index);
    frontend.reset();
    const frontend::FrontendFrame out = frontend.process(frame.left, frame.right);
    std::vector<Descriptor>& image = images.emplace_back();
    image.reserve(out.features.size());
    for (const frontend::Feature& f : out.features) image.push_back(f.descriptor);
    if (frame_indices) frame_indices->push_back(index);
    if (progress) progress(dataset.name(), images.size(), total);
  }
  return images;
}

TrainedVocabulary train_vocabulary(const TrainingOptions& options,
                                   const TrainingProgress& progress) {
  options.validate();
  TrainingSummary summary;
  summary.datasets = options.datasets.size();

  auto start = std::chrono::steady_clock::now();
  std::vector<std::vector<Descriptor>> images;
  for (const TrainingDataset& source : options.datasets) {
    const auto dataset = datasets::open_dataset(source.path, source.format, source.options);
    auto sampled = sample_left_descriptors(*dataset, options.frame_stride, options.frontend,
                                           nullptr, progress);
    std::move(sampled.begin(), sampled.end(), std::back_inserter(images));
  }
  summary.feature_seconds = seconds_since(start);
  summary.images = images.size();

  std::vector<Descriptor> all;
  for (const auto& image : images) all.insert(all.end(), image.begin(), image.end());
  summary.descriptors = all.size();
  if (all.empty()) throw std::runtime_error("vocabulary training: the datasets gave no features");

  // Seeded uniform sample without replacement (partial Fisher-Yates), kept in original order.
  if (options.max_descriptors > 0 && all.size() > options.max_descriptors) {
    synthetic::Rng rng(synthetic::derive_seed(options.vocabulary.seed, "bow-sample"));
    std::vector<std::size_t> order(all.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    for (std::size_t i = 0; i < options.max_descriptors; ++i) {
      const std::size_t j = i + static_cast<std::size_t>(rng() % (order.size() - i));
      std::swap(order[i], order[j]);
    }
    order.resize(options.max_descriptors);
    std::sort(order.begin(), order.end());
    std::vector<Descriptor> sample;
    sample.reserve(order.size());
    for (const std::size_t i : order) sample.push_back(all[i]);
    all = std::move(sample);
  }
  summary.descriptors_clustered = all.size();

  if (progress) progress("clustering", 0, 1);
  start = std::chrono::steady_clock::now();
  TrainedVocabulary out{Vocabulary::create(all, options.vocabulary, &summary.clustering), {}};
  summary.clustering_seconds = seconds_since(start);
  if (progress) progress("clustering", 1, 1);

  if (progress) progress("idf", 0, 1);
  start = std::chrono::steady_clock::now();
  const std::vector<std::size_t> images_with_word = out.vocabulary.set_idf(images);
  summary.idf_seconds = seconds_since(start);
  if (progress) progress("idf", 1, 1);

  summary.nodes = out.vocabulary.node_count();
  summary.words = out.vocabulary.word_count();
  summary.words_unseen = static_cast<std::size_t>(
      std::count(images_with_word.begin(), images_with_word.end(), std::size_t{0}));
  out.summary = summary;
  return out;
}

}  // namespace edx::bow
