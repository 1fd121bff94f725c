// The first-window check (Shi-Tomasi monitoring by inverse-compositional affine alignment):
// a known affine motion of a textured image is recovered, a track placed off its point reads
// that offset as drift, gain and bias do not, and what cannot be aligned says so.
#include "workloads/frontend/first_window.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "tests/workloads/frontend/plane_scene.hpp"

namespace edx::frontend {
namespace {

constexpr int kHalf = 10;
const cv::Point2f kFirst(200, 150);

/// The texture seen after the affine motion y = S (x - first) + q.
cv::Mat moved(const cv::Mat& texture, cv::Point2f first, const cv::Matx22d& S, cv::Point2d q) {
  const cv::Matx22d Si = S.inv();
  const cv::Vec2d t = cv::Vec2d(first.x, first.y) - Si * cv::Vec2d(q.x, q.y);
  cv::Mat out;
  cv::warpAffine(texture, out, cv::Matx23d(Si(0, 0), Si(0, 1), t[0], Si(1, 0), Si(1, 1), t[1]),
                 texture.size(), cv::INTER_LINEAR | cv::WARP_INVERSE_MAP, cv::BORDER_REFLECT_101);
  return out;
}

cv::Matx22d scaled_rotation(double scale, double radians) {
  return {scale * std::cos(radians), -scale * std::sin(radians), scale * std::sin(radians),
          scale * std::cos(radians)};
}

TEST(FirstWindow, RecoversAKnownAffineMotion) {
  // Scale 1.12, rotation 5 degrees, shear 0.04: the window's corners move up to 2 px beyond
  // its translation. Six windows on two textures (the test image's own bilinear resampling
  // limits the agreement to a few hundredths of a pixel at the centre, which is what the check
  // uses; the affine part is less well determined by a 21x21 window).
  const cv::Matx22d S = scaled_rotation(1.12, 0.09) * cv::Matx22d(1, 0.04, 0, 1);
  for (const std::uint64_t seed : {6, 7}) {
    const cv::Mat texture = testing::make_texture({400, 300}, seed);
    for (const cv::Point2f first :
         {cv::Point2f(200, 150), cv::Point2f(150, 120), cv::Point2f(250, 170)}) {
      SCOPED_TRACE(::testing::Message() << "seed " << seed << " at " << first);
      const FirstWindow window(FirstWindow::prepare(texture), first, kHalf);
      const cv::Point2d q = cv::Point2d(first) + cv::Point2d(13.3, -8.4);
      // Started 0.8 px off, as a track's own position would be.
      const auto aligned = window.align(FirstWindow::prepare(moved(texture, first, S, q)),
                                        cv::Point2f(q.x + 0.7, q.y + 0.4), 30, 0.01);
      ASSERT_TRUE(aligned.has_value());
      EXPECT_NEAR(aligned->centre.x, q.x, 0.08);
      EXPECT_NEAR(aligned->centre.y, q.y, 0.08);
      for (int r = 0; r < 2; ++r)
        for (int col = 0; col < 2; ++col) EXPECT_NEAR(aligned->A(r, col), S(r, col), 0.03);
      EXPECT_GT(aligned->iterations, 2);  // translation, then the affine warp
      EXPECT_LE(aligned->iterations, 30);
    }
  }
}

TEST(FirstWindow, ReadsATrackOffItsPointAsDriftWhateverTheExposure) {
  const cv::Mat texture = testing::make_texture({400, 300}, 9);
  const FirstWindow window(FirstWindow::prepare(texture), kFirst, kHalf);
  const cv::Point2d q(190.2, 160.7);
  cv::Mat image = moved(texture, kFirst, scaled_rotation(0.95, -0.05), q);
  image.convertTo(image, CV_8U, 0.7, 30);   // darker, lower contrast: gain 0.7, bias 30
  const cv::Point2f drifted(191.5, 159.9);  // 1.3 px right, 0.8 px up of the point
  const auto aligned = window.align(FirstWindow::prepare(image), drifted, 30, 0.01);
  ASSERT_TRUE(aligned.has_value());
  const double drift = std::hypot(aligned->centre.x - drifted.x, aligned->centre.y - drifted.y);
  EXPECT_NEAR(drift, std::hypot(1.3, 0.8), 0.06);
}

TEST(FirstWindow, SaysWhenItCannotAlign) {
  const cv::Mat flat = FirstWindow::prepare(cv::Mat(300, 400, CV_8U, cv::Scalar(90)));
  EXPECT_FALSE(FirstWindow(flat, kFirst, kHalf).align(flat, kFirst, 30, 0.01).has_value());
  // A vertical edge: no texture along it, so no affine warp is determined.
  cv::Mat edge = flat.clone();
  edge.colRange(200, 400).setTo(200);
  edge = FirstWindow::prepare(edge);
  EXPECT_FALSE(FirstWindow(edge, kFirst, kHalf).align(edge, kFirst, 30, 0.01).has_value());
  // Textured, but the window would reach past the image's border.
  const cv::Mat texture = FirstWindow::prepare(testing::make_texture({400, 300}, 3));
  const FirstWindow window(texture, kFirst, kHalf);
  EXPECT_FALSE(window.align(texture, cv::Point2f(6, 150), 30, 0.01).has_value());
  // Found where it is when nothing moved, in one or two updates.
  const auto still = window.align(texture, kFirst, 30, 0.01);
  ASSERT_TRUE(still.has_value());
  EXPECT_NEAR(still->centre.x, kFirst.x, 1e-3);
  EXPECT_NEAR(still->centre.y, kFirst.y, 1e-3);
  EXPECT_LE(still->iterations, 2);
  // One update allowed: the translation converges but the affine stage never runs. Not aligned,
  // and the update spent is reported.
  int updates = -1;
  EXPECT_FALSE(window.align(texture, kFirst, 1, 0.01, &updates).has_value());
  EXPECT_EQ(updates, 1);
}

}  // namespace
}  // namespace edx::frontend
