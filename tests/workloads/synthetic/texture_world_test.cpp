// Textures (sampling, mip levels, procedural generators) and world queries (ray cast, distance,
// texture coordinates), checked against hand-computed values; the two scenes checked for a
// closed shell and free lanes.
#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include "workloads/datasets/synthetic/random.hpp"
#include "workloads/datasets/synthetic/scenes.hpp"
#include "workloads/datasets/synthetic/texture.hpp"
#include "workloads/datasets/synthetic/texture_gen.hpp"
#include "workloads/datasets/synthetic/world.hpp"

namespace edx::synthetic {
namespace {

cv::Mat ramp_image(int size) {
  cv::Mat img(size, size, CV_8UC1);
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x)
      img.at<std::uint8_t>(y, x) = static_cast<std::uint8_t>((x * 31 + y * 17) % 256);
  }
  return img;
}

TEST(SyntheticTexture, BilinearHitsTexelCentresAndWraps) {
  const cv::Mat img = ramp_image(8);
  const Texture tex(img);
  for (int y = 0; y < 8; ++y) {
    for (int x = 0; x < 8; ++x) {
      const float u = (x + 0.5f) / 8, v = (y + 0.5f) / 8;
      EXPECT_FLOAT_EQ(tex.sample_bilinear(0, u, v), img.at<std::uint8_t>(y, x));
      EXPECT_FLOAT_EQ(tex.sample_bilinear(0, u + 1, v - 2), img.at<std::uint8_t>(y, x));
    }
  }
  // Half way between texels 2 and 3 of row 4: their mean.
  EXPECT_FLOAT_EQ(tex.sample_bilinear(0, 3.0f / 8, 4.5f / 8),
                  0.5f * (img.at<std::uint8_t>(4, 2) + img.at<std::uint8_t>(4, 3)));
  // Across the seam: between the last texel and the first (wrap-around).
  EXPECT_FLOAT_EQ(tex.sample_bilinear(0, 1.0f, 4.5f / 8),
                  0.5f * (img.at<std::uint8_t>(4, 7) + img.at<std::uint8_t>(4, 0)));
}

TEST(SyntheticTexture, MipLevelsAreBoxAveragesAndLodBlends) {
  const cv::Mat img = ramp_image(8);
  const Texture tex(img);
  ASSERT_EQ(tex.level_count(), 4);  // 8, 4, 2, 1
  const int sum = img.at<std::uint8_t>(2, 4) + img.at<std::uint8_t>(2, 5) +
                  img.at<std::uint8_t>(3, 4) + img.at<std::uint8_t>(3, 5);
  // Level-1 texel (x=2, y=1) has its centre at (2.5/4, 1.5/4).
  EXPECT_FLOAT_EQ(tex.sample_bilinear(1, 2.5f / 4, 1.5f / 4), static_cast<float>((sum + 2) / 4));
  const float u = 0.3f, v = 0.7f;
  EXPECT_FLOAT_EQ(tex.sample(u, v, 1.0f), tex.sample_bilinear(1, u, v));
  EXPECT_NEAR(tex.sample(u, v, 1.5f),
              0.5f * (tex.sample_bilinear(1, u, v) + tex.sample_bilinear(2, u, v)), 1e-4);
  EXPECT_FLOAT_EQ(tex.sample(u, v, -3.0f), tex.sample_bilinear(0, u, v));
  EXPECT_FLOAT_EQ(tex.sample(u, v, 10.0f), tex.sample_bilinear(3, u, v));
  EXPECT_THROW(Texture(cv::Mat(6, 6, CV_8UC1, cv::Scalar(0))), std::runtime_error);
  EXPECT_THROW(Texture(cv::Mat(8, 8, CV_32FC1, cv::Scalar(0))), std::runtime_error);
}

/// Mean absolute difference across the seam (last column to first, or last row to first) and
/// the largest such difference between neighbouring interior columns (rows).
std::pair<double, double> seam_and_interior(const cv::Mat& img, bool columns) {
  cv::Mat m;
  img.convertTo(m, CV_32F);
  if (!columns) m = m.t();
  const int n = m.cols;
  double interior = 0;
  for (int x = 0; x + 1 < n; ++x) {
    interior = std::max(interior, cv::norm(m.col(x), m.col(x + 1), cv::NORM_L1) / m.rows);
  }
  const double seam = cv::norm(m.col(n - 1), m.col(0), cv::NORM_L1) / m.rows;
  return {seam, interior};
}

TEST(SyntheticTexture, GeneratorsAreDeterministicTileableAndDetailed) {
  for (int k = 0; k <= static_cast<int>(TextureKind::kClouds); ++k) {
    const auto kind = static_cast<TextureKind>(k);
    SCOPED_TRACE(std::string(to_string(kind)));
    const cv::Mat a = make_texture_image(kind, 42, 256);
    const cv::Mat b = make_texture_image(kind, 42, 256);
    const cv::Mat c = make_texture_image(kind, 43, 256);
    ASSERT_EQ(a.type(), CV_8UC1);
    ASSERT_EQ(a.size(), cv::Size(256, 256));
    EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0.0);
    EXPECT_GT(cv::norm(a, c, cv::NORM_L1), 0.0);
    cv::Scalar mean, stddev;
    cv::meanStdDev(a, mean, stddev);
    EXPECT_GT(stddev[0], 8.0) << "flat texture";
    // Tiles seamlessly: the step across the seam is no larger than the largest interior step
    // (a texture cut from a non-periodic image would have a distinct jump there).
    for (const bool columns : {true, false}) {
      const auto [seam, interior] = seam_and_interior(a, columns);
      EXPECT_LE(seam, interior + 1.0) << (columns ? "columns" : "rows");
    }
  }
  EXPECT_THROW(make_texture_image(TextureKind::kBricks, 1, 100), std::runtime_error);
}

TEST(SyntheticTexture, CornersAtSeveralScales) {
  // The textures meant to carry features have FAST corners at full and at quarter resolution.
  for (const auto kind :
       {TextureKind::kConcrete, TextureKind::kBricks, TextureKind::kCardboard, TextureKind::kPoster,
        TextureKind::kFacade, TextureKind::kAsphalt, TextureKind::kClutter}) {
    SCOPED_TRACE(std::string(to_string(kind)));
    const cv::Mat img = make_texture_image(kind, 7, 512);
    cv::Mat quarter;
    cv::resize(img, quarter, cv::Size(128, 128), 0, 0, cv::INTER_AREA);
    std::vector<cv::KeyPoint> full_corners, quarter_corners;
    cv::FAST(img, full_corners, 20, true);
    cv::FAST(quarter, quarter_corners, 20, true);
    EXPECT_GT(full_corners.size(), 100u);
    EXPECT_GT(quarter_corners.size(), 20u);
  }
}

/// A world of two unit-section boxes on the x axis, one 8x8 texture.
World two_box_world() {
  World w;
  const int tex = w.add_texture(Texture(ramp_image(8)));
  Material m;
  m.texture = tex;
  m.tile_u_m = 2.0f;
  m.tile_v_m = 1.0f;
  const auto mat = static_cast<std::uint16_t>(w.add_material(m));
  Box a;
  a.min = {2, -1, -1};
  a.max = {3, 1, 1};
  a.face_material.fill(mat);
  a.uv_origin = {2, -1, 1};
  w.add_box(a);
  Box b = a;
  b.min = {5, -1, -1};
  b.max = {6, 1, 1};
  b.uv_origin = {5, -1, 1};
  w.add_box(b);
  return w;
}

TEST(SyntheticWorld, CastFindsTheNearestBoxAndItsFace) {
  const World w = two_box_world();
  Hit h = w.cast({0, 0, 0}, {1, 0, 0});
  EXPECT_FLOAT_EQ(h.t, 2.0f);
  EXPECT_EQ(h.box, 0);
  EXPECT_EQ(h.face, 0);  // -x face
  h = w.cast({0, 0, 0}, {-1, 0, 0});
  EXPECT_EQ(h.box, -1);
  EXPECT_TRUE(std::isinf(h.t));
  h = w.cast({10, 0.5f, 0}, {-1, 0, 0});
  EXPECT_FLOAT_EQ(h.t, 4.0f);
  EXPECT_EQ(h.box, 1);
  EXPECT_EQ(h.face, 1);  // +x face
  h = w.cast({2.5f, 0, 5}, {0, 0, -1});
  EXPECT_FLOAT_EQ(h.t, 4.0f);
  EXPECT_EQ(h.face, 5);  // top
  h = w.cast({0, 0, 0}, {1, 0, 0}, 1.5f);
  EXPECT_EQ(h.box, -1);  // beyond t_max
  // Oblique: from (0, -3, 0) towards (2.5, 1, 0) enters box 0 through its -y face at y = -1.
  const Eigen::Vector3f d = Eigen::Vector3f(2.5f, 2.0f, 0).normalized();
  h = w.cast({0, -3, 0}, d);
  EXPECT_EQ(h.face, 2);
  EXPECT_NEAR(h.t, std::sqrt(2.5 * 2.5 + 2.0 * 2.0), 1e-5);
}

TEST(SyntheticWorld, DistanceToGeometry) {
  const World w = two_box_world();
  EXPECT_DOUBLE_EQ(w.distance_to_geometry({0, 0, 0}), 2.0);
  EXPECT_DOUBLE_EQ(w.distance_to_geometry({2.5, 3, 0}), 2.0);
  EXPECT_DOUBLE_EQ(w.distance_to_geometry({2.5, 0, 0}), 0.0);
  EXPECT_NEAR(w.distance_to_geometry({7, 2, 2}), std::sqrt(3.0), 1e-12);
  EXPECT_DOUBLE_EQ(w.distance_to_geometry({4, 0, 0}), 1.0);
}

TEST(SyntheticWorld, TextureCoordinatesRunToTheViewersRight) {
  const World w = two_box_world();
  // -y face (seen from -y): u grows with +x, v grows downwards, one tile = 2 m x 1 m.
  Eigen::Vector2f uv = w.face_uv(0, 2, {2.5f, -1, 0.5f});
  EXPECT_FLOAT_EQ(uv.x(), 0.25f);
  EXPECT_FLOAT_EQ(uv.y(), 0.5f);
  // +y face (seen from +y): u grows with -x.
  uv = w.face_uv(0, 3, {2.5f, 1, 0.5f});
  EXPECT_FLOAT_EQ(uv.x(), -0.25f);
  // +x face (seen from +x): u grows with +y; -x face: with -y.
  EXPECT_FLOAT_EQ(w.face_uv(0, 1, {3, 0, 0}).x(), 0.5f);
  EXPECT_FLOAT_EQ(w.face_uv(0, 0, {2, 0, 0}).x(), -0.5f);
  // Top: u along x, v along y.
  uv = w.face_uv(0, 5, {3, 0, 1});
  EXPECT_FLOAT_EQ(uv.x(), 0.5f);
  EXPECT_FLOAT_EQ(uv.y(), 1.0f);
  // A copy shades exactly like the original (texture pointers refreshed).
  const World copy = w;
  EXPECT_FLOAT_EQ(copy.shade(0, 2, {2.5f, -1, 0.5f}, 0.01f),
                  w.shade(0, 2, {2.5f, -1, 0.5f}, 0.01f));
}

TEST(SyntheticWorld, FastLog2) {
  for (double x = 1e-6; x < 1e6; x *= 1.37) {
    EXPECT_NEAR(fast_log2(static_cast<float>(x)), std::log2(x), 0.01) << x;
  }
}

/// Fraction of rays from p (random directions) that hit geometry.
double closed_fraction(const World& w, const Eigen::Vector3f& p, bool downward_only) {
  Rng rng(5);
  int hits = 0, total = 0;
  for (int i = 0; i < 300; ++i) {
    Eigen::Vector3f d(static_cast<float>(normal(rng)), static_cast<float>(normal(rng)),
                      static_cast<float>(normal(rng)));
    d.normalize();
    if (downward_only && d.z() > -0.01f) continue;
    ++total;
    if (w.cast(p, d).box >= 0) ++hits;
  }
  return static_cast<double>(hits) / total;
}

TEST(SyntheticScenes, WarehouseIsClosedAndItsLanesAreFree) {
  const Scene s = build_warehouse(11);
  EXPECT_FALSE(s.outdoor);
  EXPECT_GT(s.world.boxes().size(), 1000u);
  EXPECT_FALSE(s.world.sky().enabled);
  ASSERT_EQ(s.lanes.nodes.size(), 12u);
  for (std::size_t n = 0; n < s.lanes.nodes.size(); ++n) {
    const Eigen::Vector2d a = s.lanes.nodes[n];
    EXPECT_DOUBLE_EQ(
        closed_fraction(s.world,
                        Eigen::Vector3f(static_cast<float>(a.x()), static_cast<float>(a.y()), 1.5f),
                        false),
        1.0);
    for (const int m : s.lanes.neighbours[n]) {
      const Eigen::Vector2d b = s.lanes.nodes[static_cast<std::size_t>(m)];
      for (double f = 0; f <= 1.0; f += 0.02) {
        const Eigen::Vector2d p = a + f * (b - a);
        for (const double z : {s.motion.min_height_m, s.motion.max_height_m}) {
          EXPECT_GE(s.world.distance_to_geometry({p.x(), p.y(), z}),
                    s.motion.lateral_wander_m + s.motion.clearance_m + 0.1)
              << p.transpose() << " z " << z;
        }
      }
    }
  }
}

TEST(SyntheticScenes, StreetLanesAreFreeAndTheGroundIsEverywhere) {
  const Scene s = build_street(11);
  EXPECT_TRUE(s.outdoor);
  EXPECT_TRUE(s.world.sky().enabled);
  EXPECT_GT(s.world.boxes().size(), 1000u);
  ASSERT_EQ(s.lanes.nodes.size(), 9u);
  for (std::size_t n = 0; n < s.lanes.nodes.size(); ++n) {
    const Eigen::Vector2d a = s.lanes.nodes[n];
    EXPECT_DOUBLE_EQ(
        closed_fraction(s.world,
                        Eigen::Vector3f(static_cast<float>(a.x()), static_cast<float>(a.y()), 1.6f),
                        true),
        1.0);
    for (const int m : s.lanes.neighbours[n]) {
      const Eigen::Vector2d b = s.lanes.nodes[static_cast<std::size_t>(m)];
      const Eigen::Vector2d dir = (b - a).normalized();
      const Eigen::Vector2d right(dir.y(), -dir.x());
      for (double f = 0; f <= 1.0; f += 0.01) {
        // The right lane at camera height keeps well clear of parked cars and street furniture.
        const Eigen::Vector2d p = a + f * (b - a) + s.motion.lane_offset_m * right;
        EXPECT_GE(s.world.distance_to_geometry({p.x(), p.y(), 1.65}), 1.5) << p.transpose();
      }
    }
  }
}

}  // namespace
}  // namespace edx::synthetic
