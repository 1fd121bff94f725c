#pragma once
// A textured plane seen by a rectified stereo pair, with disparity and image motion known in
// closed form, for checking the frontend against hand-computable truth.
//
// The left view at time t is a window of a large texture T shifted by the motion m_t:
//   left_t(x, y) = T(x + ox - m_t.x, y + oy - m_t.y),
// so a texture point seen at left pixel p at t = 0 is seen at p + m_t. The plane's disparity
// varies linearly along the row, d(x_l) = a + b x_l, so the right view satisfies
//   right_t(x_r, y) = left_t(x_l, y) with x_r = x_l - d(x_l), i.e. x_l = (x_r + a) / (1 - b).
#include <cstdint>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

namespace edx::frontend::testing {

/// Random rectangles and discs of random grey levels on a grey background: corner-rich.
/// `contrast` scales every shape's difference from the background grey.
inline cv::Mat make_texture(cv::Size size, std::uint64_t seed, double contrast = 1.0,
                            int shapes = 0) {
  cv::RNG rng(seed);
  cv::Mat texture(size, CV_8U, cv::Scalar(128));
  if (shapes <= 0) shapes = size.area() / 700;
  for (int i = 0; i < shapes; ++i) {
    const int grey = cvRound(128 + contrast * (rng.uniform(0, 256) - 128));
    const cv::Point corner(rng.uniform(0, size.width), rng.uniform(0, size.height));
    if (rng.uniform(0, 3) == 0) {
      cv::circle(texture, corner, rng.uniform(3, 14), cv::Scalar(grey), cv::FILLED, cv::LINE_AA);
    } else {
      const cv::Size extent(rng.uniform(4, 36), rng.uniform(4, 36));
      cv::rectangle(texture, cv::Rect(corner, extent), cv::Scalar(grey), cv::FILLED);
    }
  }
  cv::GaussianBlur(texture, texture, cv::Size(3, 3), 0.8);
  return texture;
}

struct PlaneScene {
  cv::Mat texture;
  cv::Point2d origin{100, 100};  ///< (ox, oy): texture pixel under left pixel (0, 0) at t = 0
  double disparity_at_0 = 12.3;  ///< a
  double disparity_slope = 0.0;  ///< b
  cv::Size image_size{640, 400};

  double disparity(double x_left) const { return disparity_at_0 + disparity_slope * x_left; }

  cv::Mat left(cv::Point2d motion = {}) const {
    const cv::Matx23d map(1, 0, origin.x - motion.x, 0, 1, origin.y - motion.y);
    return warp(map);
  }
  cv::Mat right(cv::Point2d motion = {}) const {
    const double s = 1.0 / (1.0 - disparity_slope);
    const cv::Matx23d map(s, 0, disparity_at_0 * s + origin.x - motion.x, 0, 1,
                          origin.y - motion.y);
    return warp(map);
  }

 private:
  cv::Mat warp(const cv::Matx23d& destination_to_texture) const {
    cv::Mat out;
    cv::warpAffine(texture, out, cv::Mat(destination_to_texture), image_size,
                   cv::INTER_LINEAR | cv::WARP_INVERSE_MAP, cv::BORDER_REFLECT_101);
    return out;
  }
};

}  // namespace edx::frontend::testing
