#pragma once
// Tiny, valid datasets written into a temporary folder, which the bad-input tests then break
// one file at a time.
#include <filesystem>
#include <string>

#include "workloads/datasets/dataset.hpp"

namespace edx::datasets::testing {

/// A fresh empty folder under the system temp directory, removed with its content on scope exit.
class TempFolder {
 public:
  explicit TempFolder(const std::string& name);
  ~TempFolder();
  TempFolder(const TempFolder&) = delete;
  TempFolder& operator=(const TempFolder&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

void write_text(const std::filesystem::path& file, const std::string& text);
std::string read_text(const std::filesystem::path& file);
/// Replaces the first occurrence of `from` in `file` by `to` (the test fails if absent).
void replace_in_file(const std::filesystem::path& file, const std::string& from,
                     const std::string& to);

/// Geometry of the tiny EuRoC folder: 64x48 pinhole cameras, no distortion, cam1 0.1 m along
/// the cam0 x axis, frames every 50 ms from kTinyStartNs.
inline constexpr int kTinyWidth = 64;
inline constexpr int kTinyHeight = 48;
inline constexpr int kTinyFrames = 5;
inline constexpr TimestampNs kTinyStartNs = 1'000'000'000;
inline constexpr TimestampNs kTinyFrameStepNs = 50'000'000;
/// Intensity of every pixel of frame i, left and right alike: a fingerprint of the pair.
inline int tiny_frame_intensity(int frame) { return 40 + 30 * frame; }

/// Writes a valid EuRoC ASL folder (mav0 with cam0, cam1, imu0, ground truth, gps0) into `root`.
void write_tiny_euroc(const std::filesystem::path& root);
/// Path of the image of `camera` ("cam0"/"cam1") for frame `frame` of the tiny EuRoC folder.
std::filesystem::path tiny_euroc_image(const std::filesystem::path& root, const std::string& camera,
                                       int frame);

/// Writes a valid KITTI odometry root (sequences/07 with 3 frames of 40x30 images, poses/07.txt).
void write_tiny_kitti(const std::filesystem::path& root);

}  // namespace edx::datasets::testing
