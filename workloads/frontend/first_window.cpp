#include "workloads/frontend/first_window.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <opencv2/imgproc.hpp>

namespace edx::frontend {
namespace {

/// I(W(x)) for the window's pixels, row-major: pixel (u, v) samples `image` (CV_32F) at
/// A (u - h, v - h) + c by bilinear interpolation. Not cv::warpAffine: its bilinear weights are
/// quantized to 1/32 px (INTER_BITS), and the Gauss-Newton steps then cycle by that much
/// instead of converging. Every sample must lie inside the image (the window's corners do).
void sample(const cv::Mat& image, const Eigen::Matrix2d& A, const Eigen::Vector2d& c, int half,
            Eigen::VectorXd& out) {
  const int side = 2 * half + 1;
  out.resize(side * side);
  const auto step = static_cast<std::ptrdiff_t>(image.step1());
  const int max_x = image.cols - 2, max_y = image.rows - 2;
  for (int v = 0; v < side; ++v) {
    // Along a row the sample point moves by A's first column.
    Eigen::Vector2d p = A * Eigen::Vector2d(-half, v - half) + c;
    for (int u = 0; u < side; ++u, p += A.col(0)) {
      const int x0 = std::min(static_cast<int>(p.x()), max_x);
      const int y0 = std::min(static_cast<int>(p.y()), max_y);
      const double ax = p.x() - x0, ay = p.y() - y0;
      const float* top = image.ptr<float>(y0) + x0;
      const float* bottom = top + step;
      out[v * side + u] = (1 - ay) * ((1 - ax) * top[0] + ax * top[1]) +
                          ay * ((1 - ax) * bottom[0] + ax * bottom[1]);
    }
  }
}

}  // namespace

cv::Mat FirstWindow::prepare(const cv::Mat& image) {
  cv::Mat smoothed;
  image.convertTo(smoothed, CV_32F);
  cv::GaussianBlur(smoothed, smoothed, {2 * kSmoothingRadius + 1, 2 * kSmoothingRadius + 1},
                   kSmoothingSigma);
  return smoothed;
}

FirstWindow::FirstWindow(const cv::Mat& prepared, cv::Point2f centre, int half) : half_(half) {
  const int side = 2 * half + 1;
  // One pixel more on each side for the central differences.
  cv::Mat patch;
  cv::getRectSubPix(prepared, {side + 2, side + 2}, centre, patch, CV_32F);
  template_.resize(side * side);
  sd_.resize(side * side, 6);
  for (int v = 0; v < side; ++v) {
    const float* above = patch.ptr<float>(v);
    const float* row = patch.ptr<float>(v + 1);
    const float* below = patch.ptr<float>(v + 2);
    for (int u = 0; u < side; ++u) {
      const int k = v * side + u;
      template_[k] = row[u + 1];
      // dT/dx, dT/dy by central differences; dW/dp = [[x, 0, y, 0, 1, 0], [0, x, 0, y, 0, 1]].
      const double gx = 0.5 * (row[u + 2] - row[u]), gy = 0.5 * (below[u + 1] - above[u + 1]);
      const double x = u - half, y = v - half;
      sd_.row(k) << gx * x, gy * x, gx * y, gy * y, gx, gy;
    }
  }
  // Gain and bias, I(W(x)) = (1 + g) T(x) + b, are projected out (Hager and Belhumeur 1998;
  // Baker and Matthews' "project out" algorithm): the steepest-descent images are made
  // orthogonal to the appearance basis {1, T}, so the update sees no gain or bias change.
  template_.array() -= template_.mean();
  const double template_norm = template_.norm();
  if (template_norm > 1e-6) {
    const Eigen::VectorXd unit = template_ / template_norm;
    sd_.rowwise() -= sd_.colwise().mean();
    sd_ -= unit * (unit.transpose() * sd_);
  }
  const Eigen::Matrix<double, 6, 6> hessian = sd_.transpose() * sd_;
  hessian_.compute(hessian);
  translation_hessian_.compute(hessian.bottomRightCorner<2, 2>());
  // A window without texture in some direction of the warp cannot be aligned: the Hessian's
  // smallest eigenvalue must be a fair share of its largest.
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eigen(hessian,
                                                                         Eigen::EigenvaluesOnly);
  textured_ = template_norm > 1e-6 && eigen.eigenvalues()[0] > 1e-6 * eigen.eigenvalues()[5];
}

std::optional<WindowAlignment> FirstWindow::align(const cv::Mat& prepared, cv::Point2f position,
                                                  int max_iterations, double epsilon_px,
                                                  int* updates) const {
  int spent = 0;
  auto out = solve(prepared, cv::Matx22f::eye(), position, true, max_iterations, epsilon_px, spent);
  if (updates != nullptr) *updates = spent;
  return out;
}

std::optional<WindowAlignment> FirstWindow::refine(const cv::Mat& prepared,
                                                   const WindowAlignment& start, int max_iterations,
                                                   double epsilon_px, int* updates) const {
  int spent = 0;
  auto out = solve(prepared, start.A, start.centre, false, max_iterations, epsilon_px, spent);
  if (updates != nullptr) *updates = spent;
  return out;
}

std::optional<WindowAlignment> FirstWindow::solve(const cv::Mat& prepared, const cv::Matx22f& A0,
                                                  cv::Point2f position, bool translation_first,
                                                  int max_iterations, double epsilon_px,
                                                  int& updates) const {
  updates = 0;
  if (!textured_) return std::nullopt;
  const double h = half_;
  const std::array<Eigen::Vector2d, 4> corners{Eigen::Vector2d(-h, -h), Eigen::Vector2d(h, -h),
                                               Eigen::Vector2d(-h, h), Eigen::Vector2d(h, h)};
  Eigen::Matrix2d A;
  A << A0(0, 0), A0(0, 1), A0(1, 0), A0(1, 1);
  Eigen::Vector2d c(position.x, position.y);
  // From a cold start, translation first (A fixed), then the whole affine warp from there: the
  // affine update alone can leave its basin from a start a pixel or two off.
  bool affine = !translation_first;
  Eigen::VectorXd sampled;
  for (int iteration = 1; iteration <= max_iterations; ++iteration) {
    for (const Eigen::Vector2d& corner : corners) {
      const Eigen::Vector2d p = A * corner + c;
      if (p.x() < 0 || p.y() < 0 || p.x() > prepared.cols - 1 || p.y() > prepared.rows - 1) {
        return std::nullopt;
      }
    }
    updates = iteration;
    // e = I(W(x)) - T(x); dp = H^-1 SD^T e (SD's columns sum to 0 and are orthogonal to T,
    // so neither the template's mean nor its gain enters).
    sample(prepared, A, c, half_, sampled);
    const Eigen::VectorXd error = sampled - template_;
    Params dp = Params::Zero();
    if (affine) {
      dp = hessian_.solve(sd_.transpose() * error);
    } else {
      dp.tail<2>() = translation_hessian_.solve(sd_.rightCols<2>().transpose() * error);
    }
    // W(dp) = (I + D) x + d; W <- W o W(dp)^-1: A <- A (I + D)^-1, c <- c - A d.
    Eigen::Matrix2d D;
    D << dp[0], dp[2], dp[1], dp[3];
    const Eigen::Vector2d d(dp[4], dp[5]);
    A = A * (Eigen::Matrix2d::Identity() + D).inverse();
    c -= A * d;
    double moved = 0;
    for (const Eigen::Vector2d& corner : corners) moved = std::max(moved, (D * corner + d).norm());
    if (moved <= epsilon_px && !affine) {
      affine = true;
    } else if (moved <= epsilon_px) {
      WindowAlignment out;
      out.centre = cv::Point2f(static_cast<float>(c.x()), static_cast<float>(c.y()));
      out.A = cv::Matx22f(static_cast<float>(A(0, 0)), static_cast<float>(A(0, 1)),
                          static_cast<float>(A(1, 0)), static_cast<float>(A(1, 1)));
      out.iterations = iteration;
      return out;
    }
  }
  return std::nullopt;
}

}  // namespace edx::frontend
