#pragma once
// Pairing of the left and right images a dataset lists, shared by every reader.
#include <filesystem>
#include <string_view>
#include <vector>

#include "workloads/datasets/dataset.hpp"

namespace edx::datasets {

/// An image as a dataset lists it: its time stamp and the file it should be in.
struct ListedImage {
  TimestampNs t_ns = 0;
  std::filesystem::path file;
};

/// A left and a right image taken at the same time.
struct StereoImagePair {
  TimestampNs t_ns = 0;
  std::filesystem::path left, right;
};

/// Drops listed images whose file does not exist, then pairs the remaining left and right
/// images that carry the same time stamp (both lists sorted by strictly increasing time).
/// Every kind of skip is counted in `report` (rows, missing images, unpaired images) and
/// logged once as a spdlog warning saying how many and of which camera (`left_label`,
/// `right_label`, e.g. the data.csv files); `report.warnings` keeps the same lines.
std::vector<StereoImagePair> pair_stereo_images(const std::vector<ListedImage>& left,
                                                const std::vector<ListedImage>& right,
                                                std::string_view left_label,
                                                std::string_view right_label, LoadReport& report);

}  // namespace edx::datasets
