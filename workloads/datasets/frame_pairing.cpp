#include "workloads/datasets/frame_pairing.hpp"

#include <fmt/core.h>
#include <spdlog/spdlog.h>

namespace edx::datasets {
namespace {

void warn(LoadReport& report, std::string message) {
  spdlog::warn("{}", message);
  report.warnings.push_back(std::move(message));
}

/// Keeps the images whose file exists; counts and reports the others.
std::vector<ListedImage> existing_images(const std::vector<ListedImage>& listed,
                                         std::string_view label, std::size_t& missing_count,
                                         LoadReport& report) {
  std::vector<ListedImage> existing;
  existing.reserve(listed.size());
  const ListedImage* first_missing = nullptr;
  for (const auto& image : listed) {
    std::error_code error;
    if (std::filesystem::is_regular_file(image.file, error)) {
      existing.push_back(image);
    } else if (first_missing == nullptr) {
      first_missing = &image;
    }
  }
  missing_count = listed.size() - existing.size();
  if (missing_count > 0) {
    warn(report, fmt::format("{}: {} of {} listed images do not exist and are skipped (first: {})",
                             label, missing_count, listed.size(), first_missing->file.string()));
  }
  return existing;
}

}  // namespace

std::vector<StereoImagePair> pair_stereo_images(const std::vector<ListedImage>& left,
                                                const std::vector<ListedImage>& right,
                                                std::string_view left_label,
                                                std::string_view right_label, LoadReport& report) {
  report.left_rows = left.size();
  report.right_rows = right.size();
  const auto left_images = existing_images(left, left_label, report.left_missing_images, report);
  const auto right_images =
      existing_images(right, right_label, report.right_missing_images, report);

  // Merge of two time-sorted lists: equal stamps pair, the smaller unmatched stamp is skipped.
  std::vector<StereoImagePair> pairs;
  std::size_t l = 0, r = 0;
  const ListedImage *first_left_unpaired = nullptr, *first_right_unpaired = nullptr;
  while (l < left_images.size() || r < right_images.size()) {
    if (r == right_images.size() ||
        (l < left_images.size() && left_images[l].t_ns < right_images[r].t_ns)) {
      if (first_left_unpaired == nullptr) first_left_unpaired = &left_images[l];
      ++report.left_unpaired;
      ++l;
    } else if (l == left_images.size() || right_images[r].t_ns < left_images[l].t_ns) {
      if (first_right_unpaired == nullptr) first_right_unpaired = &right_images[r];
      ++report.right_unpaired;
      ++r;
    } else {
      pairs.push_back({left_images[l].t_ns, left_images[l].file, right_images[r].file});
      ++l;
      ++r;
    }
  }
  if (report.left_unpaired > 0) {
    warn(report, fmt::format("{}: {} images have no {} image with the same time stamp and are "
                             "skipped (first: {})",
                             left_label, report.left_unpaired, right_label,
                             first_left_unpaired->file.string()));
  }
  if (report.right_unpaired > 0) {
    warn(report, fmt::format("{}: {} images have no {} image with the same time stamp and are "
                             "skipped (first: {})",
                             right_label, report.right_unpaired, left_label,
                             first_right_unpaired->file.string()));
  }
  return pairs;
}

}  // namespace edx::datasets
