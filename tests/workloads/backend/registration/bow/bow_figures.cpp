// edx_bow_figures: the figures of docs/BOW.md. Trains the default vocabulary on EuRoC-layout
// datasets through the real frontend, saves it, and times transform and database queries.
//   edx_bow_figures OUT.bin STRIDE DATASET...
#include <time.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>

#include "workloads/backend/registration/bow/database.hpp"
#include "workloads/backend/registration/bow/training.hpp"

/// CPU time of the calling thread, s: stable on a loaded host, unlike wall time.
double thread_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

int main(int argc, char** argv) {
  using namespace edx;
  using Clock = std::chrono::steady_clock;
  if (argc < 4) {
    std::fprintf(stderr, "usage: %s OUT.bin STRIDE DATASET...\n", argv[0]);
    return 2;
  }
  bow::TrainingOptions options;
  options.frame_stride = std::stoi(argv[2]);
  for (int i = 3; i < argc; ++i) options.datasets.push_back({argv[i], {}, {}});
  std::printf("options: %s\n", options.to_json().dump().c_str());
  const auto start = Clock::now();
  const bow::TrainedVocabulary trained = bow::train_vocabulary(options);
  const double total_s = std::chrono::duration<double>(Clock::now() - start).count();
  trained.vocabulary.save(argv[1]);
  std::printf("summary: %s\ntotal training %.2f s, file %ju bytes\n",
              trained.summary.to_json().dump().c_str(), total_s,
              static_cast<std::uintmax_t>(std::filesystem::file_size(argv[1])));

  // Transform and query timing on the first dataset's frames (every 5th, fresh detections).
  const auto dataset = datasets::open_dataset(options.datasets.front().path, {}, {});
  const auto images = bow::sample_left_descriptors(*dataset, 5, options.frontend);
  std::size_t descriptors = 0;
  bow::Database database;
  auto t0 = Clock::now();
  const double cpu0 = thread_cpu_seconds();
  for (int repeat = 0; repeat < 5; ++repeat) {
    for (const auto& image : images) {
      bow::BowVector bow;
      bow::FeatureVector features;
      trained.vocabulary.transform(image, 2, bow, features);
      descriptors += image.size();
      if (repeat == 0) database.add(bow, std::move(features));
    }
  }
  const double transform_s = std::chrono::duration<double>(Clock::now() - t0).count();
  const double transform_cpu_s = thread_cpu_seconds() - cpu0;
  const double thousands = static_cast<double>(descriptors) / 1000.0;
  std::printf(
      "transform: %zu descriptors, per 1000 descriptors (incl. direct index): %.3f ms wall, "
      "%.3f ms thread CPU\n",
      descriptors, 1e3 * transform_s / thousands, 1e3 * transform_cpu_s / thousands);
  std::size_t postings = 0;
  t0 = Clock::now();
  for (const auto& image : images) {
    bow::QueryStats stats;
    database.query(trained.vocabulary.transform(image), 5, &stats);
    postings += stats.postings;
  }
  const double query_s = std::chrono::duration<double>(Clock::now() - t0).count();
  std::printf(
      "query (transform + inverse index) of %zu images against %zu: %.3f ms each, "
      "%.0f postings each\n",
      images.size(), database.size(), 1e3 * query_s / static_cast<double>(images.size()),
      static_cast<double>(postings) / static_cast<double>(images.size()));
  return 0;
}
