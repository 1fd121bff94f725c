#pragma once
// Vocabulary training on datasets (what `edx vocab` runs): every frame_stride-th frame of each
// dataset goes through the real stereo frontend, reset before each sampled frame so its left
// features are detections of that frame alone; their ORB descriptors are the training images.
// At most max_descriptors of them (a seeded uniform sample) are clustered into the tree; the
// IDF weights are computed over all sampled frames.
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <string_view>
#include <vector>

#include "workloads/backend/registration/bow/vocabulary.hpp"
#include "workloads/datasets/dataset.hpp"
#include "workloads/frontend/frontend_options.hpp"

namespace edx::bow {

struct TrainingDataset {
  std::filesystem::path path;  ///< as open_dataset takes it (EuRoC: folder holding mav0/)
  datasets::DatasetFormat format = datasets::DatasetFormat::kEuroc;
  datasets::DatasetOptions options;  ///< resize, rectification, KITTI sequence
};

struct TrainingOptions {
  std::vector<TrainingDataset> datasets;
  int frame_stride = 10;  ///< frames 0, n, 2n, ... of each dataset
  /// Descriptors clustered at most (a seeded uniform sample of all); 0: all of them.
  std::size_t max_descriptors = 300'000;
  VocabularyOptions vocabulary;
  /// The frontend that extracts the features; LK iteration counting is off by default since
  /// nothing is tracked (the frontend is reset before every sampled frame).
  frontend::FrontendOptions frontend = [] {
    frontend::FrontendOptions o;
    o.count_lk_iterations = false;
    return o;
  }();

  /// Throws std::runtime_error naming the first bad field (no datasets, stride < 1, ...).
  void validate() const;
  nlohmann::json to_json() const;
};

struct TrainingSummary {
  std::size_t datasets = 0;
  std::size_t images = 0;                 ///< sampled frames (training images, N of the IDF)
  std::size_t descriptors = 0;            ///< their left-image descriptors
  std::size_t descriptors_clustered = 0;  ///< after the max_descriptors sample
  std::size_t nodes = 0;
  std::size_t words = 0;
  std::size_t words_unseen = 0;  ///< words no training image contains (weight 0)
  ClusteringStats clustering;
  double feature_seconds = 0;     ///< frontend on the sampled frames (incl. image loading)
  double clustering_seconds = 0;  ///< tree construction
  double idf_seconds = 0;         ///< transforming all images for the IDF
  nlohmann::json to_json() const;
};

struct TrainedVocabulary {
  Vocabulary vocabulary;
  TrainingSummary summary;
};

/// Progress: stage ("features" per dataset path, "clustering", "idf"), done, total.
using TrainingProgress =
    std::function<void(std::string_view stage, std::size_t done, std::size_t total)>;

/// Left-image descriptors of frames 0, stride, 2 stride, ... of `dataset`, one vector per frame,
/// from the stereo frontend reset before each frame. `frame_indices` receives the frames used.
std::vector<std::vector<Descriptor>> sample_left_descriptors(
    const datasets::Dataset& dataset, int stride, const frontend::FrontendOptions& options,
    std::vector<std::size_t>* frame_indices = nullptr, const TrainingProgress& progress = {});

/// Trains a vocabulary on the datasets (see the file comment). Deterministic for the options
/// (seed included). Throws std::runtime_error on bad options or datasets, or when the datasets
/// give no descriptor.
TrainedVocabulary train_vocabulary(const TrainingOptions& options,
                                   const TrainingProgress& progress = {});

}  // namespace edx::bow
