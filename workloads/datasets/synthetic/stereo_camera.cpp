#include "workloads/datasets/synthetic/stereo_camera.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "common/parallel.hpp"
#include "workloads/datasets/synthetic/random.hpp"

namespace edx::synthetic {

namespace {

/// Approximately standard normal value from one 64-bit hash: the sum of four 16-bit uniforms
/// (Irwin–Hall, variance 4/12) rescaled to unit variance.
inline float hashed_normal(std::uint64_t h) {
  const std::uint64_t a = h & 0xFFFF, b = (h >> 16) & 0xFFFF, c = (h >> 32) & 0xFFFF, d = h >> 48;
  const float sum = static_cast<float>(a + b + c + d) * (1.0f / 65536.0f);  // mean 2
  return (sum - 2.0f) * 1.7320508f;
}

}  // namespace

ExposureProcess::ExposureProcess(std::uint64_t seed, const ImageSensorOptions& options)
    : state_(seed), options_(options) {}

double ExposureProcess::next() {
  if (!options_.enabled) return 1.0;
  Rng rng(state_);
  state_ = rng();
  log_gain_ = std::clamp(0.97 * log_gain_ + options_.exposure_walk * normal(rng),
                         -options_.exposure_range, options_.exposure_range);
  return std::exp(log_gain_);
}

cv::Mat expose_image(const cv::Mat& radiance, double gain, std::uint64_t noise_seed,
                     const ImageSensorOptions& options) {
  cv::Mat out(radiance.size(), CV_8UC1);
  if (!options.enabled) {
    radiance.convertTo(out, CV_8UC1);
    return out;
  }
  cv::Mat blurred;
  if (options.blur_sigma_px > 0) {
    const int k = 2 * static_cast<int>(std::ceil(3 * options.blur_sigma_px)) + 1;
    cv::GaussianBlur(radiance, blurred, cv::Size(k, k), options.blur_sigma_px,
                     options.blur_sigma_px, cv::BORDER_REFLECT101);
  } else {
    blurred = radiance;
  }
  const float g = static_cast<float>(gain);
  const float sigma = static_cast<float>(options.noise_sigma);
  for (int y = 0; y < out.rows; ++y) {
    const float* in = blurred.ptr<float>(y);
    std::uint8_t* o = out.ptr<std::uint8_t>(y);
    const std::uint64_t row_seed = mix64(noise_seed + static_cast<std::uint64_t>(y));
    for (int x = 0; x < out.cols; ++x) {
      const float noise = sigma * hashed_normal(mix64(row_seed + static_cast<std::uint64_t>(x)));
      // Round half up after clipping to [0, 255].
      const float v = std::clamp(g * in[x] + noise, 0.0f, 255.0f);
      o[x] = static_cast<std::uint8_t>(static_cast<int>(v + 0.5f));
    }
  }
  return out;
}

StereoCamera::StereoCamera(const World& world, const StereoRig& rig,
                           const ImageSensorOptions& options, std::uint64_t seed, int threads)
    : rig_(rig),
      options_(options),
      seed_(seed),
      threads_(std::max(1, threads)),
      renderer_(world, threads),
      exposure_(derive_seed(seed, "exposure"), options) {}

PinholeCamera StereoCamera::camera() const {
  return PinholeCamera{rig_.width, rig_.height, rig_.fx, rig_.fy, rig_.cx, rig_.cy};
}

StereoImages StereoCamera::capture(const Eigen::Isometry3d& T_world_body) {
  const PinholeCamera cam = camera();
  const std::vector<RenderView> views = {{cam, T_world_body * rig_.T_body_left},
                                         {cam, T_world_body * rig_.T_body_right()}};
  renderer_.render(views, radiance_);
  StereoImages images;
  images.gain_left = exposure_.next();
  images.gain_right =
      options_.enabled ? images.gain_left * (1.0 + options_.stereo_gain_mismatch) : 1.0;
  const std::uint64_t frame = frame_++;
  std::array<cv::Mat, 2> result;
  common::parallel_for(2, threads_, [&](int i) {
    const double gain = i == 0 ? images.gain_left : images.gain_right;
    const std::uint64_t noise_seed =
        derive_seed(seed_, i == 0 ? "noise_left" : "noise_right", frame);
    result[static_cast<std::size_t>(i)] =
        expose_image(radiance_[static_cast<std::size_t>(i)], gain, noise_seed, options_);
  });
  images.left = result[0];
  images.right = result[1];
  return images;
}

void StereoCamera::skip() {
  exposure_.next();
  ++frame_;
}

}  // namespace edx::synthetic
