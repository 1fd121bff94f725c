// Rendering: the tiled ray caster against a brute-force cast, stereo disparity of a
// fronto-parallel wall measured from the images (phase correlation) against f b / Z, the sensor
// model's statistics, thread independence, and trackability of rendered sequences (FAST corners
// and pyramidal LK with a forward-backward check) indoors and outdoors.
#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include "workloads/datasets/synthetic/random.hpp"
#include "workloads/datasets/synthetic/renderer.hpp"
#include "workloads/datasets/synthetic/rig.hpp"
#include "workloads/datasets/synthetic/scenes.hpp"
#include "workloads/datasets/synthetic/stereo_camera.hpp"
#include "workloads/datasets/synthetic/texture_gen.hpp"
#include "workloads/datasets/synthetic/trajectory.hpp"

namespace edx::synthetic {
namespace {

PinholeCamera camera_of(const StereoRig& rig) {
  return {rig.width, rig.height, rig.fx, rig.fy, rig.cx, rig.cy};
}

std::vector<Eigen::Vector3d> camera_points(const StereoRig& rig) {
  return {rig.T_body_left.translation(), rig.T_body_right().translation()};
}

TEST(SyntheticRender, TiledRendererAgreesWithBruteForceCast) {
  for (const bool outdoor : {false, true}) {
    SCOPED_TRACE(outdoor ? "street" : "warehouse");
    const Scene scene = outdoor ? build_street(1) : build_warehouse(1);
    const StereoRig rig = make_rig(outdoor ? RigKind::kCar : RigKind::kEuroc, Resolution{320, 200});
    const PlannedTrajectory planned = plan_trajectory(scene, 5.0, 2, camera_points(rig));
    Renderer renderer(scene.world, 2);
    std::vector<cv::Mat> radiance, depth;
    const Eigen::Isometry3d T_wc = planned.trajectory.at(2.0).T_world_body() * rig.T_body_left;
    renderer.render({{camera_of(rig), T_wc}}, radiance, &depth);
    int compared = 0, mismatched = 0, sky = 0;
    for (int y = 0; y < rig.height; y += 3) {
      for (int x = 0; x < rig.width; x += 3) {
        const Eigen::Vector3d d_cam((x - rig.cx) / rig.fx, (y - rig.cy) / rig.fy, 1.0);
        const Eigen::Vector3f d = (T_wc.linear() * d_cam.normalized()).cast<float>();
        const Hit hit = scene.world.cast(T_wc.translation().cast<float>(), d);
        const float t = depth[0].at<float>(y, x);
        ++compared;
        if (hit.box < 0) {
          ++sky;
          if (!std::isinf(t)) ++mismatched;
        } else if (std::abs(t - hit.t) > 1e-3f + 1e-4f * hit.t) {
          ++mismatched;
        }
      }
    }
    // Rays grazing a box edge may differ in the last bit of their direction.
    EXPECT_LT(mismatched, compared / 500 + 1) << mismatched << " of " << compared;
    if (outdoor) {
      EXPECT_GT(sky, 0);
    } else {
      EXPECT_EQ(sky, 0);
    }
    EXPECT_LT(renderer.last_stats().box_tests, 20 * renderer.last_stats().rays);
  }
}

/// A world of one textured wall whose -x face lies at x = wall_x.
World wall_world(double wall_x) {
  World w;
  const int tex = w.add_texture(Texture(make_texture_image(TextureKind::kClutter, 3, 512)));
  Material m;
  m.texture = tex;
  m.tile_u_m = m.tile_v_m = 3.0f;
  const auto mat = static_cast<std::uint16_t>(w.add_material(m));
  Box b;
  b.min = Eigen::Vector3f(static_cast<float>(wall_x), -100, -100);
  b.max = Eigen::Vector3f(static_cast<float>(wall_x) + 1, 100, 100);
  b.face_material.fill(mat);
  b.uv_origin = {0, 0, 0};
  w.add_box(b);
  return w;
}

TEST(SyntheticRender, StereoDisparityOfAFrontoParallelWallIsFbOverZ) {
  struct Case {
    RigKind rig;
    double depth;
  };
  for (const Case c : {Case{RigKind::kEuroc, 2.5}, Case{RigKind::kEuroc, 6.0},
                       Case{RigKind::kCar, 8.0}, Case{RigKind::kCar, 20.0}}) {
    const StereoRig rig = make_rig(c.rig, native_resolution(c.rig));
    // Body at the origin, level: the cameras look along +x; the wall is `depth` ahead of them.
    const double wall_x = rig.T_body_left.translation().x() + c.depth;
    const World world = wall_world(wall_x);
    StereoCamera camera(world, rig, ImageSensorOptions{}, 4, 2);
    const StereoImages images = camera.capture(Eigen::Isometry3d::Identity());
    const int win = 256;
    const cv::Rect roi((rig.width - win) / 2, (rig.height - win) / 2, win, win);
    cv::Mat left, right, hann;
    images.left(roi).convertTo(left, CV_64F);
    images.right(roi).convertTo(right, CV_64F);
    cv::createHanningWindow(hann, roi.size(), CV_64F);
    const cv::Point2d shift = cv::phaseCorrelate(right, left, hann);
    const double expected = rig.fx * rig.baseline_m / c.depth;
    const double error = std::abs(shift.x - expected);
    std::printf(
        "[ figures ] %s rig, wall at %.1f m: disparity %.3f px measured, %.3f px = f b / Z, error "
        "%.3f px\n",
        std::string(to_string(c.rig)).c_str(), c.depth, shift.x, expected, error);
    EXPECT_LT(error, 0.1) << "depth " << c.depth;
    EXPECT_LT(std::abs(shift.y), 0.1);
  }
}

TEST(SyntheticRender, SensorModelGainNoiseAndDeterminism) {
  const cv::Mat radiance(200, 300, CV_32FC1, cv::Scalar(100.0f));
  ImageSensorOptions o;
  o.noise_sigma = 2.0;
  const cv::Mat a = expose_image(radiance, 1.1, 17, o);
  cv::Scalar mean, stddev;
  cv::meanStdDev(a, mean, stddev);
  EXPECT_NEAR(mean[0], 110.0, 0.1);
  EXPECT_NEAR(stddev[0], std::sqrt(2.0 * 2.0 + 1.0 / 12), 0.1);  // noise plus rounding
  EXPECT_EQ(cv::norm(a, expose_image(radiance, 1.1, 17, o), cv::NORM_INF), 0.0);
  EXPECT_GT(cv::norm(a, expose_image(radiance, 1.1, 18, o), cv::NORM_L1), 0.0);
  o.enabled = false;
  const cv::Mat ideal = expose_image(radiance, 1.3, 17, o);
  EXPECT_EQ(cv::countNonZero(ideal != 100), 0);
  // Exposure: a bounded walk with frame-to-frame changes of about 1 %.
  ExposureProcess exposure(3, ImageSensorOptions{});
  double prev = exposure.next(), lo = prev, hi = prev;
  for (int k = 0; k < 500; ++k) {
    const double g = exposure.next();
    EXPECT_LT(std::abs(std::log(g / prev)), 0.05);
    lo = std::min(lo, g);
    hi = std::max(hi, g);
    prev = g;
  }
  EXPECT_GT(hi / lo, 1.05);
  EXPECT_LE(hi, std::exp(0.15) + 1e-12);
}

TEST(SyntheticRender, ImagesDoNotDependOnTheThreadCount) {
  const Scene scene = build_warehouse(4);
  const StereoRig rig = make_rig(RigKind::kEuroc, Resolution{376, 240});
  const PlannedTrajectory planned = plan_trajectory(scene, 2.0, 1, camera_points(rig));
  StereoCamera one(scene.world, rig, ImageSensorOptions{}, 8, 1);
  StereoCamera two(scene.world, rig, ImageSensorOptions{}, 8, 2);
  for (int k = 0; k < 2; ++k) {
    const Eigen::Isometry3d T = planned.trajectory.at(0.05 * k).T_world_body();
    const StereoImages a = one.capture(T), b = two.capture(T);
    EXPECT_EQ(cv::norm(a.left, b.left, cv::NORM_INF), 0.0);
    EXPECT_EQ(cv::norm(a.right, b.right, cv::NORM_INF), 0.0);
  }
}

struct Trackability {
  std::size_t corners = 0;
  double tracked_fraction = 0;
};

/// FAST (threshold 20) on frame a, pyramidal LK to frame b, kept when the status is ok and
/// tracking back lands within 1 px of the start.
Trackability track(const cv::Mat& a, const cv::Mat& b) {
  std::vector<cv::KeyPoint> keypoints;
  cv::FAST(a, keypoints, 20, true);
  Trackability out;
  out.corners = keypoints.size();
  if (keypoints.empty()) return out;
  std::vector<cv::Point2f> p0, p1, p0_back;
  cv::KeyPoint::convert(keypoints, p0);
  std::vector<unsigned char> status, status_back;
  std::vector<float> err;
  const cv::Size window(21, 21);
  const cv::TermCriteria criteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 30, 0.01);
  cv::calcOpticalFlowPyrLK(a, b, p0, p1, status, err, window, 3, criteria);
  cv::calcOpticalFlowPyrLK(b, a, p1, p0_back, status_back, err, window, 3, criteria);
  std::size_t good = 0;
  for (std::size_t i = 0; i < p0.size(); ++i) {
    if (status[i] && status_back[i] && cv::norm(p0[i] - p0_back[i]) < 1.0) ++good;
  }
  out.tracked_fraction = static_cast<double>(good) / static_cast<double>(p0.size());
  return out;
}

TEST(SyntheticRender, FastCornersAndLkTrackingIndoorsAndOutdoors) {
  for (const bool outdoor : {false, true}) {
    const char* name = outdoor ? "outdoor" : "indoor";
    SCOPED_TRACE(name);
    const Scene scene =
        outdoor ? build_street(derive_seed(1, "world")) : build_warehouse(derive_seed(1, "world"));
    // 752x480 frames; outdoors the car rig scaled to that size.
    const StereoRig rig = make_rig(outdoor ? RigKind::kCar : RigKind::kEuroc, Resolution{752, 480});
    const PlannedTrajectory planned =
        plan_trajectory(scene, 30.0, derive_seed(1, "run", 0), camera_points(rig));
    StereoCamera camera(scene.world, rig, ImageSensorOptions{}, 1, 2);
    for (const double t : {1.0, 9.0, 17.0, 25.0}) {
      // Consecutive 20 Hz frames (the exposure evolves between them as in a sequence).
      const cv::Mat a = camera.capture(planned.trajectory.at(t).T_world_body()).left;
      const cv::Mat b = camera.capture(planned.trajectory.at(t + 0.05).T_world_body()).left;
      const Trackability r = track(a, b);
      std::printf("[ figures ] %s t=%.0f s: %zu FAST corners, %.1f %% tracked by LK (FB < 1 px)\n",
                  name, t, r.corners, 100.0 * r.tracked_fraction);
      EXPECT_GE(r.corners, 300u) << "t " << t;
      EXPECT_GE(r.tracked_fraction, 0.90) << "t " << t;
    }
  }
}

}  // namespace
}  // namespace edx::synthetic
