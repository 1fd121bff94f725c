#pragma once
// Feature monitoring against a track's first window (Shi and Tomasi, "Good Features to Track",
// CVPR 1994, Sec. 4). Frame-to-frame LK (temporal_tracker.hpp) follows the image by translation
// only: where the perspective or the scale of the scene under a window changes, the window
// slides a fraction of a pixel a frame and the slides add up along the track. Aligning the
// track's first window itself into the current image under an affine warp measures that drift:
//
//   W(x; A, c) = A x + c,   x the centred window coordinates (-h..h), c the window's centre,
//
// started at A = I and c = the track's current position; drift = |c* - position|.
//
// The alignment is Baker and Matthews' inverse-compositional Gauss-Newton ("Lucas-Kanade 20
// Years On", IJCV 2004, Sec. 3.2) on images smoothed once per frame (prepare()): the template's
// steepest-descent images SD and Hessian H = SD^T SD are computed once per track; from a cold
// start translation is aligned first, then the whole warp; each iteration samples the image
// under the current warp (bilinear), solves H dp = SD^T (I(W(x)) - T(x)) and composes
// W <- W o W(dp)^-1. Gain and bias, I(W(x)) = (1 + g) T(x) + b, are projected out of SD (Hager
// and Belhumeur 1998), so exposure changes do not read as drift.
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <optional>

namespace edx::frontend {

/// Where a first window lands in a later image.
struct WindowAlignment {
  cv::Point2f centre;  ///< c*: the aligned window centre (image pixels)
  cv::Matx22f A;       ///< the affine part of the warp
  int iterations = 0;  ///< Gauss-Newton updates computed
};

/// A track's first window, prepared for inverse-compositional alignment.
class FirstWindow {
 public:
  /// An image as the check reads it (once per frame): float, smoothed by a Gaussian of
  /// kSmoothingSigma, as KLT implementations smooth before taking gradients; it widens the
  /// Gauss-Newton iteration's basin on sharp texture.
  static cv::Mat prepare(const cv::Mat& image);

  /// Cuts the (2 half + 1)^2 window around `centre` from a prepare()d image.
  FirstWindow(const cv::Mat& prepared, cv::Point2f centre, int half);

  /// Aligns the window into a prepare()d image starting at A = I, c = `position`. Stops when an
  /// update moves no window corner by more than `epsilon_px`. nullopt when the template has too
  /// little texture for an affine warp, the warped window leaves the image, or
  /// `max_iterations` do not converge.
  /// `updates`, when given, receives the Gauss-Newton updates computed, aligned or not.
  std::optional<WindowAlignment> align(const cv::Mat& prepared, cv::Point2f position,
                                       int max_iterations, double epsilon_px,
                                       int* updates = nullptr) const;

  /// Warm start: aligns from a previous alignment moved to this image (A = start.A, c =
  /// start.centre), the whole affine warp at once. A track's warp changes little from frame to
  /// frame, so this takes a few updates where align() takes ten or more.
  std::optional<WindowAlignment> refine(const cv::Mat& prepared, const WindowAlignment& start,
                                        int max_iterations, double epsilon_px,
                                        int* updates = nullptr) const;

  /// prepare()'s Gaussian: sigma (px) and kernel radius.
  static constexpr double kSmoothingSigma = 1.0;
  static constexpr int kSmoothingRadius = 3;

 private:
  using Params = Eigen::Matrix<double, 6, 1>;
  std::optional<WindowAlignment> solve(const cv::Mat& prepared, const cv::Matx22f& A0,
                                       cv::Point2f position, bool translation_first,
                                       int max_iterations, double epsilon_px, int& updates) const;
  int half_;
  Eigen::VectorXd template_;  ///< zero-mean template, row-major
  /// Steepest-descent images [gx x, gy x, gx y, gy y, gx, gy], one row per window pixel.
  Eigen::Matrix<double, Eigen::Dynamic, 6> sd_;
  Eigen::LDLT<Eigen::Matrix<double, 6, 6>> hessian_;
  Eigen::LDLT<Eigen::Matrix2d> translation_hessian_;  ///< of the translation columns alone
  bool textured_ = false;
};

}  // namespace edx::frontend
