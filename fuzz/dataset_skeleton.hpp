#pragma once
// A minimal valid dataset on disk (two 96x64 stereo frames) for the dataset fuzz targets: the
// fuzz input replaces one of its text files (the first byte picks which), the reader opens it,
// and the file is restored afterwards.
#include <cstdint>
#include <exception>
#include <filesystem>
#include <map>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "fuzz/fuzz_input.hpp"
#include "workloads/datasets/dataset.hpp"
#include "workloads/datasets/png_io.hpp"

namespace edx::fuzz {

struct DatasetSkeleton {
  std::filesystem::path root;                   ///< what the reader opens
  std::vector<std::string> files;               ///< replaceable text files, relative to root
  std::map<std::string, std::string> contents;  ///< their valid contents

  /// Lists the files, writes every file and a 96x64 gray image per `images` entry (relative).
  void write(const std::vector<std::string>& images) {
    files.clear();
    for (const auto& [file, text] : contents) files.push_back(file);
    for (const auto& [file, text] : contents) {
      std::filesystem::create_directories((root / file).parent_path());
      write_bytes(root / file, text);
    }
    cv::Mat image(64, 96, CV_8U);
    cv::randu(image, 0, 255);
    for (const std::string& relative : images) {
      std::filesystem::create_directories((root / relative).parent_path());
      datasets::write_png_gray(root / relative, image);
    }
  }
  /// Replaces the file the first byte selects with the rest of the input; returns it.
  std::string replace(const std::uint8_t* data, std::size_t size) const {
    const std::string& file = files[data[0] % files.size()];
    write_bytes(root / file, as_text(data + 1, size - 1));
    return file;
  }
  void restore(const std::string& file) const { write_bytes(root / file, contents.at(file)); }
  /// One fuzz input: replace a file, open the dataset as `format` and read its first frame (a
  /// std::exception is a valid rejection), restore the file.
  void run(const std::uint8_t* data, std::size_t size, datasets::DatasetFormat format) const {
    if (size == 0) return;
    const std::string replaced = replace(data, size);
    try {
      const auto dataset = datasets::open_dataset(root, format);
      if (dataset->frame_count() > 0) (void)dataset->load_frame(0);
    } catch (const std::exception&) {
    }
    restore(replaced);
  }
};

}  // namespace edx::fuzz
