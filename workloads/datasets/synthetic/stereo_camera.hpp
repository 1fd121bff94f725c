#pragma once
// The simulated stereo camera: renders the rig's two rectified views and turns radiance into
// 8-bit images the way a sensor would: exposure gain (a slow random walk, slightly different
// for the right camera), optical blur (Gaussian), read noise (Gaussian), rounding and clipping:
//   I = clamp(round(g * (G_sigma * L) + n), 0, 255),  n ~ N(0, noise_sigma^2).
// The noise of pixel i in frame k is a function of (seed, k, camera, i) only, so images do not
// depend on the number of threads.
#include <Eigen/Geometry>
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "workloads/datasets/synthetic/renderer.hpp"
#include "workloads/datasets/synthetic/rig.hpp"
#include "workloads/datasets/synthetic/world.hpp"

namespace edx::synthetic {

struct ImageSensorOptions {
  bool enabled = true;           ///< false: ideal images (radiance rounded, no blur/noise/gain)
  double blur_sigma_px = 0.6;    ///< Gaussian optical blur
  double noise_sigma = 1.5;      ///< read noise, gray levels
  double exposure_walk = 0.01;   ///< std dev of the per-frame step of log gain
  double exposure_range = 0.15;  ///< bound of |log gain|
  double stereo_gain_mismatch = 0.01;  ///< right gain = left gain * (1 + mismatch)
};

/// Log-gain AR(1) process x_{k+1} = 0.97 x_k + walk * n_k, clamped to +-range; gain = exp(x).
class ExposureProcess {
 public:
  ExposureProcess(std::uint64_t seed, const ImageSensorOptions& options);
  /// Gain of the next frame (left camera).
  double next();

 private:
  std::uint64_t state_;
  ImageSensorOptions options_;
  double log_gain_ = 0;
};

/// Applies gain, blur, noise and quantization to a radiance image (CV_32FC1) -> CV_8UC1.
cv::Mat expose_image(const cv::Mat& radiance, double gain, std::uint64_t noise_seed,
                     const ImageSensorOptions& options);

struct StereoImages {
  cv::Mat left, right;  ///< CV_8UC1
  double gain_left = 1, gain_right = 1;
};

class StereoCamera {
 public:
  StereoCamera(const World& world, const StereoRig& rig, const ImageSensorOptions& options,
               std::uint64_t seed, int threads = 2);

  /// Captures the next frame from body pose T_world_body (frames must be captured in order:
  /// the exposure evolves from frame to frame).
  StereoImages capture(const Eigen::Isometry3d& T_world_body);
  /// Passes over the next frame without rendering it: the exposure walk and the frame count
  /// (the noise seed) advance as capture() advances them, so a later frame is the same image as
  /// in a run that captured every frame.
  void skip();

  PinholeCamera camera() const;
  const StereoRig& rig() const { return rig_; }
  const Renderer& renderer() const { return renderer_; }

 private:
  StereoRig rig_;
  ImageSensorOptions options_;
  std::uint64_t seed_;
  int threads_;
  Renderer renderer_;
  ExposureProcess exposure_;
  std::uint64_t frame_ = 0;
  std::vector<cv::Mat> radiance_;
};

}  // namespace edx::synthetic
