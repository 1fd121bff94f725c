// The registration backend on maps built in memory (no images): random map points with random
// ORB descriptors seen from a few keyframes, and frames whose features are those points
// projected at a known pose with a few descriptor bits flipped. Checks relocalization (BoW
// query, matching, PnP, refinement, projection), tracking by projection on the next frame, the
// recorded kernels (the projection as one gemm over all M points), the failure status on an
// unrelated map and on a frame without features, and the constructor's checks.
#include "workloads/backend/registration/registration_backend.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>

#include "workloads/backend/so3.hpp"
#include "workloads/frontend/stereo_frontend.hpp"

namespace edx::backend::registration {
namespace {

BackendCamera camera() {
  BackendCamera c;
  c.width = 640;
  c.height = 480;
  c.fx = c.fy = 400;
  c.cx = 320;
  c.cy = 240;
  c.baseline_m = 0.1;
  // Body = IMU 5 cm behind the camera, camera looking along body x (as EuRoC-like rigs).
  c.T_body_left.linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  c.T_body_left.translation() = Eigen::Vector3d(0.05, 0, 0);
  return c;
}

slam::Descriptor random_descriptor(std::mt19937& rng) {
  slam::Descriptor d;
  for (auto& byte : d) byte = static_cast<std::uint8_t>(rng() & 0xFF);
  return d;
}

Eigen::Isometry3d body_pose(double x, double yaw) {
  // World z up; the body looks along world +x at yaw 0 (camera z = body x).
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(0, x, 1.0);
  return T;
}

/// Pixel of a world point seen from a body pose, if in the image and in front.
std::optional<Eigen::Vector2d> project(const BackendCamera& c, const Eigen::Isometry3d& T_wb,
                                       const Eigen::Vector3d& X) {
  const Eigen::Vector3d P = (T_wb * c.T_body_left).inverse() * X;
  if (P.z() < 0.5) return std::nullopt;
  const Eigen::Vector2d uv(c.fx * P.x() / P.z() + c.cx, c.fy * P.y() / P.z() + c.cy);
  if (uv.x() < 0 || uv.y() < 0 || uv.x() >= c.width || uv.y() >= c.height) return std::nullopt;
  return uv;
}

struct TestWorld {
  std::shared_ptr<slam::Map> map = std::make_shared<slam::Map>();
  std::shared_ptr<bow::Vocabulary> vocabulary;
};

/// Map points in a slab 4..10 m ahead (world +x), keyframes along the y axis.
TestWorld make_world(std::uint32_t seed, int points = 600) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  TestWorld w;
  const BackendCamera c = camera();
  w.map->camera = c;
  for (int i = 0; i < points; ++i) {
    slam::MapLandmark l;
    l.id = i;
    l.track_id = i;
    l.position = Eigen::Vector3d(4 + 6 * u(rng), -5 + 10 * u(rng), -2 + 6 * u(rng));
    l.descriptor = random_descriptor(rng);
    w.map->landmarks.push_back(l);
  }
  std::vector<std::vector<bow::Descriptor>> images;
  for (int k = 0; k < 5; ++k) {
    slam::MapKeyframe kf;
    kf.id = k;
    kf.T_world_body = body_pose(-1.0 + 0.5 * k, 0.0);
    images.emplace_back();
    for (auto& l : w.map->landmarks) {
      const auto uv = project(c, kf.T_world_body, l.position);
      if (!uv) continue;
      slam::MapKeypoint kp;
      kp.left = *uv;
      kp.descriptor = l.descriptor;
      l.observations.push_back({kf.id, kf.keypoints.size()});
      kf.keypoints.push_back(kp);
      images.back().push_back(l.descriptor);
    }
    w.map->keyframes.push_back(kf);
  }
  std::vector<bow::Descriptor> all;
  for (const auto& l : w.map->landmarks) all.push_back(l.descriptor);
  bow::VocabularyOptions vo;
  vo.branching = 6;
  vo.depth = 3;
  w.vocabulary = std::make_shared<bow::Vocabulary>(bow::Vocabulary::create(all, vo));
  w.vocabulary->set_idf(images);
  return w;
}

/// The frontend's view of the map points from a body pose: 0.3 px noise, 3 bits flipped.
frontend::FrontendFrame make_frame(const TestWorld& w, const Eigen::Isometry3d& T_wb,
                                   std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0, 0.3);
  frontend::FrontendFrame frame;
  for (const auto& l : w.map->landmarks) {
    const auto uv = project(camera(), T_wb, l.position);
    if (!uv) continue;
    frontend::Feature f;
    f.id = static_cast<std::int64_t>(frame.features.size());
    f.left = cv::Point2f(static_cast<float>(uv->x() + noise(rng)),
                         static_cast<float>(uv->y() + noise(rng)));
    f.descriptor = l.descriptor;
    for (int b = 0; b < 3; ++b) {
      const unsigned bit = rng() % 256;
      f.descriptor[bit / 8] ^= static_cast<std::uint8_t>(1u << (bit % 8));
    }
    frame.features.push_back(f);
  }
  return frame;
}

BackendInput input_of(const frontend::FrontendFrame& frame, std::int64_t t_ns) {
  BackendInput in;
  in.t_ns = t_ns;
  in.frontend = &frame;
  return in;
}

const trace::KernelRecord* find_kernel(const BackendOutput& out, const std::string& name) {
  for (const auto& k : out.kernels) {
    if (k.kernel == name) return &k;
  }
  return nullptr;
}

TEST(RegistrationBackend, RelocalizesThenTracksByProjection) {
  const TestWorld w = make_world(11);
  RegistrationBackend backend(camera(), RegistrationOptions{}, w.map, w.vocabulary);
  EXPECT_EQ(backend.keyframes(), 5u);
  EXPECT_EQ(backend.map_points(), 600u);

  // Between keyframes 2 and 3, turned by 3 degrees.
  const Eigen::Isometry3d truth1 = body_pose(0.2, 0.05);
  const auto frame1 = make_frame(w, truth1, 1);
  ASSERT_GT(frame1.features.size(), 100u);
  const BackendOutput out1 = backend.process(input_of(frame1, 1));
  ASSERT_EQ(out1.status, "ok");
  ASSERT_TRUE(out1.T_world_body);
  EXPECT_LT((out1.T_world_body->translation() - truth1.translation()).norm(), 0.01);
  EXPECT_LT(so3_log(out1.T_world_body->linear().transpose() * truth1.linear()).norm(), 1e-3);
  std::vector<std::string> names;
  for (const auto& k : out1.kernels) names.push_back(k.kernel);
  const std::vector<std::string> relocalization = {
      "bow_query",           "matching",       "pnp", "pose_refinement", "local_map", "projection",
      "projection_matching", "pose_refinement"};
  EXPECT_TRUE(std::search(names.begin(), names.end(), relocalization.begin() + 2,
                          relocalization.end()) != names.end());
  EXPECT_EQ(names.front(), "bow_query");
  EXPECT_EQ(names[1], "matching");
  EXPECT_EQ(backend.statistics().relocalized, 1);

  // The current map: every keyframe shares points with the others here, so the local map is
  // all 5 keyframes and the M points they observe.
  std::int64_t observed = 0;
  for (const auto& l : w.map->landmarks) observed += l.observations.empty() ? 0 : 1;
  const trace::KernelRecord* local = find_kernel(out1, "local_map");
  ASSERT_NE(local, nullptr);
  EXPECT_EQ(local->n, 5);
  EXPECT_EQ(local->k, observed);
  // The projection kernel: accelerable, m = M, one gemm C (3x4) times X (4xM).
  const trace::KernelRecord* projection = find_kernel(out1, "projection");
  ASSERT_NE(projection, nullptr);
  EXPECT_TRUE(projection->accelerable);
  EXPECT_EQ(projection->m, observed);
  // Visible: the points seen in the frame (up to a few at the border of the image).
  EXPECT_NEAR(static_cast<double>(projection->n), static_cast<double>(frame1.features.size()), 3);
  ASSERT_EQ(projection->ops.size(), 1u);
  EXPECT_EQ(projection->ops[0].op, trace::Op::Gemm);
  EXPECT_EQ(projection->ops[0].m, 3);
  EXPECT_EQ(projection->ops[0].n, observed);
  EXPECT_EQ(projection->ops[0].k, 4);
  for (const auto& k : out1.kernels) {
    EXPECT_EQ(k.accelerable, k.kernel == "projection") << k.kernel;
    EXPECT_GE(k.host_ns, 0);
  }

  // Next frame 5 cm on: tracked from the previous pose, no BoW query.
  const Eigen::Isometry3d truth2 = body_pose(0.25, 0.06);
  const auto frame2 = make_frame(w, truth2, 2);
  const BackendOutput out2 = backend.process(input_of(frame2, 2));
  ASSERT_EQ(out2.status, "ok");
  EXPECT_LT((out2.T_world_body->translation() - truth2.translation()).norm(), 0.01);
  EXPECT_EQ(out2.kernels.front().kernel, "local_map");
  EXPECT_EQ(out2.kernels[1].kernel, "projection");
  EXPECT_EQ(find_kernel(out2, "bow_query"), nullptr);
  EXPECT_EQ(backend.statistics().tracked, 1);
  const trace::KernelRecord* refinement = find_kernel(out2, "pose_refinement");
  ASSERT_NE(refinement, nullptr);
  EXPECT_GE(refinement->n, static_cast<std::int64_t>(0.9 * frame2.features.size()));
}

TEST(RegistrationBackend, SameInputGivesTheSamePoses) {
  const TestWorld w = make_world(5);
  const auto frame = make_frame(w, body_pose(-0.3, -0.04), 9);
  RegistrationBackend a(camera(), RegistrationOptions{}, w.map, w.vocabulary);
  RegistrationBackend b(camera(), RegistrationOptions{}, w.map, w.vocabulary);
  const BackendOutput pa = a.process(input_of(frame, 1)), pb = b.process(input_of(frame, 1));
  ASSERT_TRUE(pa.T_world_body && pb.T_world_body);
  EXPECT_TRUE(pa.T_world_body->matrix() == pb.T_world_body->matrix());
}

TEST(RegistrationBackend, FailsWithAStatusAndNoPoseOnAnUnrelatedMap) {
  const TestWorld w = make_world(11);
  const TestWorld other = make_world(12);  // other points, other descriptors
  RegistrationBackend backend(camera(), RegistrationOptions{}, other.map, other.vocabulary);
  const auto frame = make_frame(w, body_pose(0.2, 0.05), 1);
  for (int i = 0; i < 2; ++i) {
    const BackendOutput out = backend.process(input_of(frame, i + 1));
    EXPECT_FALSE(out.T_world_body);
    EXPECT_EQ(out.status.rfind("registration_failed: ", 0), 0u) << out.status;
    ASSERT_FALSE(out.kernels.empty());
    EXPECT_EQ(out.kernels.front().kernel, "bow_query");  // never tracking: nothing registered
  }
  EXPECT_EQ(backend.statistics().failures, 2);
  EXPECT_EQ(backend.statistics().registered, 0);

  const frontend::FrontendFrame empty;
  RegistrationBackend fresh(camera(), RegistrationOptions{}, w.map, w.vocabulary);
  const BackendOutput out = fresh.process(input_of(empty, 1));
  EXPECT_FALSE(out.T_world_body);
  EXPECT_EQ(out.status, "registration_failed: no_features");
}

TEST(RegistrationBackend, LosesTrackingThenRelocalizes) {
  const TestWorld w = make_world(11);
  RegistrationBackend backend(camera(), RegistrationOptions{}, w.map, w.vocabulary);
  ASSERT_EQ(backend.process(input_of(make_frame(w, body_pose(0.0, 0.0), 1), 1)).status, "ok");
  // A frame of an unrelated world: tracking and relocalization fail.
  const TestWorld other = make_world(99);
  EXPECT_NE(backend.process(input_of(make_frame(other, body_pose(0.0, 0.0), 2), 2)).status, "ok");
  // Back in the map far from the last pose: relocalized by BoW.
  const Eigen::Isometry3d truth = body_pose(0.8, -0.05);
  const BackendOutput out = backend.process(input_of(make_frame(w, truth, 3), 3));
  ASSERT_EQ(out.status, "ok");
  EXPECT_EQ(out.kernels.front().kernel, "bow_query");
  EXPECT_LT((out.T_world_body->translation() - truth.translation()).norm(), 0.01);
  EXPECT_EQ(backend.statistics().relocalized, 2);
}

TEST(RegistrationBackend, RejectsMissingMapOrVocabulary) {
  const TestWorld w = make_world(11, 50);
  EXPECT_THROW(RegistrationBackend(camera(), RegistrationOptions{}, nullptr, w.vocabulary),
               std::runtime_error);
  EXPECT_THROW(RegistrationBackend(camera(), RegistrationOptions{}, w.map, nullptr),
               std::runtime_error);
  EXPECT_THROW(RegistrationBackend(camera(), RegistrationOptions{}, w.map,
                                   std::make_shared<bow::Vocabulary>()),
               std::runtime_error);
  EXPECT_THROW(RegistrationBackend(camera(), RegistrationOptions{}, std::make_shared<slam::Map>(),
                                   w.vocabulary),
               std::runtime_error);
  RegistrationOptions bad;
  bad.bow_ratio = 0;
  EXPECT_THROW(RegistrationBackend(camera(), bad, w.map, w.vocabulary), std::runtime_error);
}

}  // namespace
}  // namespace edx::backend::registration
