// `edx gen` output: the EuRoC layout and formats for every scenario, byte-identical output for
// identical arguments, bad arguments, images consistent with the written ground truth and
// calibration, and a round trip through the project's EuRoC reader.
#include "workloads/datasets/synthetic/generator.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "tests/support/temp_dir.hpp"
#include "tests/workloads/synthetic/synthetic_test_support.hpp"
#include "workloads/datasets/dataset.hpp"
#include "workloads/datasets/synthetic/euroc_writer.hpp"
#include "workloads/datasets/synthetic/scenes.hpp"

namespace edx::synthetic {
namespace {

namespace fs = std::filesystem;
using testing::TempDir;

GenerateOptions small_options(Scenario scenario, const fs::path& out, int frames = 3) {
  GenerateOptions o;
  o.scenario = scenario;
  o.frames = frames;
  o.resolution = Resolution{160, 120};
  o.seed = 3;
  o.out = out;
  return o;
}

void expect_mav0_layout(const fs::path& mav0, int frames, bool gps, const StereoRig& rig) {
  SCOPED_TRACE(mav0.string());
  for (const char* f :
       {"body.yaml", "cam0/data.csv", "cam0/sensor.yaml", "cam1/data.csv", "cam1/sensor.yaml",
        "imu0/data.csv", "imu0/sensor.yaml", "state_groundtruth_estimate0/data.csv",
        "state_groundtruth_estimate0/sensor.yaml"}) {
    EXPECT_TRUE(fs::is_regular_file(mav0 / f)) << f;
  }
  EXPECT_EQ(fs::exists(mav0 / "gps0" / "data.csv"), gps);
  // Headers exactly as in the real dataset (and the edx GPS extension).
  EXPECT_EQ(testing::first_line(mav0 / "cam0" / "data.csv"), "#timestamp [ns],filename");
  EXPECT_EQ(testing::first_line(mav0 / "imu0" / "data.csv"),
            "#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1],"
            "a_RS_S_x [m s^-2],a_RS_S_y [m s^-2],a_RS_S_z [m s^-2]");
  EXPECT_EQ(testing::first_line(mav0 / "state_groundtruth_estimate0" / "data.csv"),
            "#timestamp, p_RS_R_x [m], p_RS_R_y [m], p_RS_R_z [m], q_RS_w [], q_RS_x [], "
            "q_RS_y [], q_RS_z [], v_RS_R_x [m s^-1], v_RS_R_y [m s^-1], v_RS_R_z [m s^-1], "
            "b_w_RS_S_x [rad s^-1], b_w_RS_S_y [rad s^-1], b_w_RS_S_z [rad s^-1], "
            "b_a_RS_S_x [m s^-2], b_a_RS_S_y [m s^-2], b_a_RS_S_z [m s^-2]");
  for (const char* f : {"body.yaml", "cam0/sensor.yaml", "imu0/sensor.yaml",
                        "state_groundtruth_estimate0/sensor.yaml"}) {
    EXPECT_EQ(testing::first_line(mav0 / f), "%YAML:1.0") << f;
  }
  // Camera lists: one row per frame, 20 Hz, images present and of the stated size.
  const auto cams = testing::read_csv(mav0 / "cam0" / "data.csv");
  ASSERT_EQ(cams.size(), static_cast<std::size_t>(frames));
  EXPECT_EQ(testing::read_csv(mav0 / "cam1" / "data.csv"), cams);
  for (std::size_t i = 0; i < cams.size(); ++i) {
    ASSERT_EQ(cams[i].size(), 2u);
    EXPECT_EQ(cams[i][1], cams[i][0] + ".png");
    if (i > 0) {
      EXPECT_EQ(std::stoll(cams[i][0]) - std::stoll(cams[i - 1][0]), 50'000'000);
    }
    for (const char* cam : {"cam0", "cam1"}) {
      const cv::Mat img =
          cv::imread((mav0 / cam / "data" / cams[i][1]).string(), cv::IMREAD_UNCHANGED);
      ASSERT_FALSE(img.empty());
      EXPECT_EQ(img.type(), CV_8UC1);
      EXPECT_EQ(img.size(), cv::Size(rig.width, rig.height));
    }
  }
  // IMU and ground truth: 200 Hz from the first to the last frame.
  const auto imu = testing::read_numeric_csv(mav0 / "imu0" / "data.csv");
  const auto gt = testing::read_csv(mav0 / "state_groundtruth_estimate0" / "data.csv");
  EXPECT_EQ(imu.size(), static_cast<std::size_t>((frames - 1) * 10 + 1));
  EXPECT_EQ(gt.size(), imu.size());
  EXPECT_EQ(static_cast<std::int64_t>(imu.front()[0]), std::stoll(cams.front()[0]));
  EXPECT_EQ(gt.back()[0], cams.back()[0]);
  // Calibration: rectified pinhole, no distortion, cam1 = cam0 moved one baseline along x_cam.
  const auto c0 = testing::read_camera_yaml(mav0 / "cam0" / "sensor.yaml");
  const auto c1 = testing::read_camera_yaml(mav0 / "cam1" / "sensor.yaml");
  EXPECT_EQ(c0.width, rig.width);
  EXPECT_EQ(c0.height, rig.height);
  EXPECT_DOUBLE_EQ(c0.fx, rig.fx);
  EXPECT_DOUBLE_EQ(c0.cy, rig.cy);
  EXPECT_EQ(c0.distortion, std::vector<double>(4, 0.0));
  EXPECT_EQ(c1.distortion, std::vector<double>(4, 0.0));
  const Eigen::Isometry3d T01 = c0.T_BS.inverse() * c1.T_BS;
  EXPECT_LT((T01.linear() - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  EXPECT_LT((T01.translation() - Eigen::Vector3d(rig.baseline_m, 0, 0)).norm(), 1e-12);
  cv::FileStorage imu_yaml((mav0 / "imu0" / "sensor.yaml").string(), cv::FileStorage::READ);
  for (const char* key : {"gyroscope_noise_density", "gyroscope_random_walk",
                          "accelerometer_noise_density", "accelerometer_random_walk", "rate_hz"}) {
    EXPECT_FALSE(imu_yaml[key].empty()) << key;
  }
  EXPECT_DOUBLE_EQ(static_cast<double>(imu_yaml["rate_hz"]), 200.0);
  EXPECT_DOUBLE_EQ(static_cast<double>(imu_yaml["gyroscope_noise_density"]), 1.6968e-4);
  if (gps) {
    EXPECT_EQ(testing::first_line(mav0 / "gps0" / "data.csv"),
              "#timestamp [ns],p_x [m],p_y [m],p_z [m],sigma [m]");
  }
}

TEST(SyntheticGen, WritesTheEurocLayoutForEveryScenario) {
  for (const Scenario scenario : {Scenario::kIndoorUnknown, Scenario::kIndoorKnown,
                                  Scenario::kOutdoorUnknown, Scenario::kOutdoorKnown}) {
    SCOPED_TRACE(std::string(to_string(scenario)));
    TempDir dir("layout");
    const GenerateOptions o = small_options(scenario, dir.path() / "ds", 4);
    const GenerateSummary summary = generate_dataset(o);
    const bool outdoor = is_outdoor(scenario);
    EXPECT_EQ(summary.rig.kind, outdoor ? RigKind::kCar : RigKind::kEuroc);
    EXPECT_TRUE(fs::is_regular_file(o.out / "edx_gen.yaml"));
    if (has_map_run(scenario)) {
      ASSERT_EQ(summary.runs.size(), 2u);
      EXPECT_FALSE(fs::exists(o.out / "mav0"));
      expect_mav0_layout(o.out / "map" / "mav0", 4, outdoor, summary.rig);
      expect_mav0_layout(o.out / "loc" / "mav0", 4, outdoor, summary.rig);
      // The localization run is later and, by default, re-traverses the map route: same lane
      // graph nodes, starting beside the map run's start (0.3 m lane offset, +-0.45 m wander
      // of each run, heights drawn afresh), but not on the same path.
      const auto map_gt = testing::read_ground_truth(o.out / "map" / "mav0");
      const auto loc_gt = testing::read_ground_truth(o.out / "loc" / "mav0");
      EXPECT_EQ(loc_gt.front().t_ns - map_gt.front().t_ns, kLocalizationDelayNs);
      const auto& map_route = summary.runs[0].route;
      const auto& loc_route = summary.runs[1].route;
      ASSERT_GE(loc_route.size(), map_route.size());
      EXPECT_TRUE(std::equal(map_route.begin(), map_route.end(), loc_route.begin()));
      const double start_gap = (loc_gt.front().p - map_gt.front().p).head<2>().norm();
      EXPECT_LT(start_gap, 0.3 + 2 * 0.45 + 1e-6);
      EXPECT_GT((loc_gt.front().p - map_gt.front().p).norm(), 1e-3);
      std::ifstream yaml(o.out / "edx_gen.yaml");
      const std::string text((std::istreambuf_iterator<char>(yaml)), {});
      EXPECT_NE(text.find("loc_route: retraverse"), std::string::npos);
    } else {
      ASSERT_EQ(summary.runs.size(), 1u);
      expect_mav0_layout(o.out / "mav0", 4, outdoor, summary.rig);
    }
    // Nothing left beside the output.
    for (const auto& entry : fs::directory_iterator(dir.path())) {
      EXPECT_EQ(entry.path().filename(), "ds");
    }
  }
}

// The map-size option: a longer map run than loc run; the loc run re-traverses the start of the
// map route, so the map covers what it visits. Only the known scenarios have a map run.
TEST(SyntheticGen, MapFramesLengthensTheMapRunOnly) {
  TempDir dir("map_frames");
  GenerateOptions o = small_options(Scenario::kIndoorKnown, dir.path() / "ds", 4);
  o.map_frames = 9;
  const GenerateSummary summary = generate_dataset(o);
  ASSERT_EQ(summary.runs.size(), 2u);
  EXPECT_EQ(summary.runs[0].frames, 9);
  EXPECT_EQ(summary.runs[1].frames, 4);
  expect_mav0_layout(o.out / "map" / "mav0", 9, false, summary.rig);
  expect_mav0_layout(o.out / "loc" / "mav0", 4, false, summary.rig);
  EXPECT_GT(summary.runs[0].path_length_m, 1.5 * summary.runs[1].path_length_m);
  const auto& map_route = summary.runs[0].route;
  const auto& loc_route = summary.runs[1].route;
  ASSERT_FALSE(loc_route.empty());
  EXPECT_EQ(loc_route.front(), map_route.front());

  GenerateOptions unknown = small_options(Scenario::kIndoorUnknown, dir.path() / "u", 4);
  unknown.map_frames = 9;
  EXPECT_THROW(generate_dataset(unknown), std::runtime_error);
  GenerateOptions zero = small_options(Scenario::kIndoorKnown, dir.path() / "z", 4);
  zero.map_frames = 0;
  EXPECT_THROW(generate_dataset(zero), std::runtime_error);
  EXPECT_FALSE(fs::exists(dir.path() / "u"));
  EXPECT_FALSE(fs::exists(dir.path() / "z"));
}

TEST(SyntheticGen, IdenticalArgumentsGiveIdenticalBytes) {
  TempDir dir("determinism");
  GenerateOptions o = small_options(Scenario::kOutdoorKnown, dir.path() / "a", 5);
  o.resolution = Resolution{320, 240};
  o.threads = 2;
  generate_dataset(o);
  o.out = dir.path() / "b";
  o.threads = 1;  // a different thread count must not matter either
  generate_dataset(o);
  o.out = dir.path() / "c";
  o.seed = 4;
  generate_dataset(o);
  const auto a = testing::hash_tree(dir.path() / "a");
  const auto b = testing::hash_tree(dir.path() / "b");
  const auto c = testing::hash_tree(dir.path() / "c");
  EXPECT_GT(a.size(), 30u);
  EXPECT_EQ(a, b);
  // Another seed changes the images and the trajectories.
  std::size_t differing = 0;
  for (const auto& [file, hash] : a) {
    const auto it = c.find(file);
    if (it == c.end() || it->second != hash) ++differing;
  }
  EXPECT_GT(differing, a.size() / 2);
  EXPECT_NE(a.at("map/mav0/state_groundtruth_estimate0/data.csv"),
            c.at("map/mav0/state_groundtruth_estimate0/data.csv"));
}

// frame_stride: frames 0, n, 2n, ... of each run with the very images and time stamps they have
// in the full run (the exposure walk and the noise advance over the skipped frames), the
// camera rate 20/n Hz, the IMU, ground truth and GPS complete.
TEST(SyntheticGen, FrameStrideWritesTheFullRunsFramesOnly) {
  TempDir dir("frame_stride");
  GenerateOptions full = small_options(Scenario::kOutdoorKnown, dir.path() / "full", 10);
  generate_dataset(full);
  GenerateOptions sparse = full;
  sparse.out = dir.path() / "sparse";
  sparse.frame_stride = 4;
  const GenerateSummary summary = generate_dataset(sparse);
  ASSERT_EQ(summary.runs.size(), 2u);
  for (const RunSummary& run : summary.runs) {
    SCOPED_TRACE(run.name);
    EXPECT_EQ(run.frames, 3);  // frames 0, 4, 8 of 10
    const fs::path a = full.out / run.name / "mav0";
    const fs::path b = sparse.out / run.name / "mav0";
    const auto full_cams = testing::read_csv(a / "cam0" / "data.csv");
    const auto sparse_cams = testing::read_csv(b / "cam0" / "data.csv");
    ASSERT_EQ(full_cams.size(), 10u);
    ASSERT_EQ(sparse_cams.size(), 3u);
    for (std::size_t i = 0; i < sparse_cams.size(); ++i) {
      EXPECT_EQ(sparse_cams[i], full_cams[4 * i]);
      for (const char* cam : {"cam0", "cam1"}) {
        const cv::Mat x =
            cv::imread((a / cam / "data" / full_cams[4 * i][1]).string(), cv::IMREAD_UNCHANGED);
        const cv::Mat y =
            cv::imread((b / cam / "data" / sparse_cams[i][1]).string(), cv::IMREAD_UNCHANGED);
        ASSERT_FALSE(x.empty());
        ASSERT_EQ(x.size(), y.size());
        EXPECT_EQ(cv::norm(x, y, cv::NORM_INF), 0.0) << cam << " frame " << 4 * i;
      }
    }
    // Frame 4 differs from frame 0 (the test would pass on a camera that never moves).
    EXPECT_GT(
        cv::norm(cv::imread((b / "cam0" / "data" / sparse_cams[0][1]).string()),
                 cv::imread((b / "cam0" / "data" / sparse_cams[1][1]).string()), cv::NORM_INF),
        0.0);
    for (const char* file :
         {"imu0/data.csv", "state_groundtruth_estimate0/data.csv", "gps0/data.csv"}) {
      EXPECT_EQ(edx::testing::read_file(a / file), edx::testing::read_file(b / file)) << file;
    }
    cv::FileStorage cam_yaml((b / "cam0" / "sensor.yaml").string(), cv::FileStorage::READ);
    EXPECT_DOUBLE_EQ(static_cast<double>(cam_yaml["rate_hz"]), 5.0);
  }
  EXPECT_NE(edx::testing::read_file(sparse.out / "edx_gen.yaml").find("frame_stride: 4\n"),
            std::string::npos);
  EXPECT_EQ(edx::testing::read_file(full.out / "edx_gen.yaml").find("frame_stride"),
            std::string::npos);
  EXPECT_EQ(
      datasets::open_dataset(sparse.out / "loc", datasets::DatasetFormat::kEuroc)->frame_count(),
      3u);

  for (const int stride : {0, 11}) {
    GenerateOptions bad = small_options(Scenario::kIndoorUnknown, dir.path() / "bad", 10);
    bad.frame_stride = stride;
    try {
      generate_dataset(bad);
      ADD_FAILURE() << "frame stride " << stride << " accepted";
    } catch (const std::runtime_error& e) {
      EXPECT_EQ(std::string(e.what()),
                "frame stride: expected 1 to 10 (the frames), got " + std::to_string(stride));
    }
    EXPECT_FALSE(fs::exists(bad.out));
  }
}

// The PNG writer is lossless: what the camera captured is what a reader decodes, for sensor-like
// noise and for flat and saturated areas.
TEST(SyntheticGen, WrittenImagesDecodeToTheCapturedPixels) {
  TempDir dir("png");
  const StereoRig rig = make_rig(RigKind::kEuroc, Resolution{96, 64});
  EurocWriter writer(dir.path() / "mav0", rig, kCameraRateHz, "png round trip");
  cv::Mat left(64, 96, CV_8UC1), right(64, 96, CV_8UC1, cv::Scalar(255));
  cv::RNG rng(7);
  rng.fill(left, cv::RNG::UNIFORM, 0, 256);
  right(cv::Rect(10, 5, 40, 30)).setTo(0);
  writer.add_frame(kStartTimeNs, left, right);
  for (const auto& [cam, image] : {std::pair{"cam0", &left}, std::pair{"cam1", &right}}) {
    const cv::Mat read = cv::imread(
        (dir.path() / "mav0" / cam / "data" / (std::to_string(kStartTimeNs) + ".png")).string(),
        cv::IMREAD_UNCHANGED);
    ASSERT_EQ(read.type(), CV_8UC1) << cam;
    ASSERT_EQ(read.size(), image->size()) << cam;
    EXPECT_EQ(cv::norm(read, *image, cv::NORM_INF), 0.0) << cam;
  }
}

TEST(SyntheticGen, RejectsBadArguments) {
  EXPECT_THROW(parse_scenario("indoor"), std::runtime_error);
  try {
    parse_scenario("underwater");
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("underwater"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("outdoor_known"), std::string::npos);
  }
  for (const char* bad : {"abc", "752x", "x480", "752x480x3", "0x480", "752*480", "-752x480", ""}) {
    EXPECT_THROW(parse_resolution(bad), std::runtime_error) << bad;
  }
  EXPECT_EQ(parse_resolution("640x480"), (Resolution{640, 480}));
  EXPECT_THROW(parse_rig("truck"), std::runtime_error);
  EXPECT_THROW(parse_loc_route("backwards"), std::runtime_error);
  EXPECT_EQ(parse_loc_route("diverge"), RevisitMode::kDiverge);

  TempDir dir("bad_args");
  GenerateOptions o = small_options(Scenario::kIndoorUnknown, dir.path() / "out");
  o.frames = 0;
  EXPECT_THROW(generate_dataset(o), std::runtime_error);
  EXPECT_FALSE(fs::exists(o.out));
  o.frames = 2;
  o.loc_speed_scale = 0.1;
  EXPECT_THROW(generate_dataset(o), std::runtime_error);
  o.loc_speed_scale = 0.85;
  o.loc_lateral_offset_m = 3;
  EXPECT_THROW(generate_dataset(o), std::runtime_error);
  o.loc_lateral_offset_m = 0.3;
  EXPECT_FALSE(fs::exists(o.out));
  // An existing non-empty directory is refused and left untouched; --force replaces it.
  o.frames = 2;
  fs::create_directories(o.out);
  { std::ofstream(o.out / "keep.txt") << "mine"; }
  try {
    generate_dataset(o);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("not empty"), std::string::npos);
  }
  EXPECT_TRUE(fs::exists(o.out / "keep.txt"));
  EXPECT_FALSE(fs::exists(o.out / "mav0"));
  o.force = true;
  generate_dataset(o);
  EXPECT_FALSE(fs::exists(o.out / "keep.txt"));
  EXPECT_TRUE(fs::exists(o.out / "mav0" / "cam0" / "data.csv"));
  // An existing empty directory is fine without --force; a file in the way is not.
  o.force = false;
  o.out = dir.path() / "empty";
  fs::create_directories(o.out);
  generate_dataset(o);
  EXPECT_TRUE(fs::exists(o.out / "mav0"));
  o.out = dir.path() / "file";
  { std::ofstream(o.out) << "x"; }
  EXPECT_THROW(generate_dataset(o), std::runtime_error);
  // Default rig choice: by resolution, else by scenario; other resolutions scale intrinsics.
  GenerateOptions r;
  r.scenario = Scenario::kIndoorUnknown;
  r.resolution = Resolution{1280, 720};
  EXPECT_EQ(resolve_rig(r).kind, RigKind::kCar);
  r.resolution = Resolution{640, 480};
  const StereoRig scaled = resolve_rig(r);
  EXPECT_EQ(scaled.kind, RigKind::kEuroc);
  EXPECT_NEAR(scaled.fx, 458.654 * 640 / 752, 1e-9);
  EXPECT_DOUBLE_EQ(scaled.fy, scaled.fx);
  r.scenario = Scenario::kOutdoorUnknown;
  r.resolution.reset();
  EXPECT_EQ(resolve_rig(r).width, 1280);
  EXPECT_DOUBLE_EQ(resolve_rig(r).baseline_m, 0.54);
}

/// Runs the edx binary with arguments; returns the exit status and stderr.
std::pair<int, std::string> run_edx(const std::string& args, const fs::path& err_file) {
  const std::string cmd =
      std::string(EDX_BIN_DIR) + "/edx " + args + " 2>" + err_file.string() + " >/dev/null";
  const int status = std::system(cmd.c_str());
  std::ifstream in(err_file);
  std::stringstream ss;
  ss << in.rdbuf();
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, ss.str()};
}

TEST(SyntheticGen, CommandLineReportsBadArgumentsWithExitCodeOne) {
  ASSERT_TRUE(fs::exists(fs::path(EDX_BIN_DIR) / "edx")) << "build the edx target first";
  TempDir dir("cli");
  const fs::path err = dir.path() / "stderr.txt";
  const std::string out = (dir.path() / "out").string();
  struct Case {
    std::string args;
    std::string message;
  };
  fs::create_directories(dir.path() / "full");
  { std::ofstream(dir.path() / "full" / "x") << "x"; }
  for (const Case& c :
       {Case{"gen --scenario moon --out " + out, "scenario 'moon'"},
        Case{"gen --scenario indoor_unknown --resolution abc --out " + out, "resolution 'abc'"},
        Case{"gen --scenario indoor_unknown --frames 0 --out " + out, "frames"},
        Case{"gen --scenario indoor_unknown --frames 2 --out " + (dir.path() / "full").string(),
             "not empty"}}) {
    const auto [code, text] = run_edx(c.args, err);
    EXPECT_EQ(code, 1) << c.args;
    EXPECT_EQ(text.rfind("edx: error: ", 0), 0u) << text;
    EXPECT_NE(text.find(c.message), std::string::npos) << text;
    EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 1) << text;
  }
  EXPECT_FALSE(fs::exists(out));
  // A good run writes the dataset and reports progress on stderr.
  const auto [code, text] = run_edx(
      "gen --scenario outdoor_unknown --frames 3 --resolution 96x64 --seed 2 --out " + out, err);
  EXPECT_EQ(code, 0) << text;
  EXPECT_NE(text.find("3/3 frames"), std::string::npos) << text;
  EXPECT_TRUE(fs::exists(fs::path(out) / "mav0" / "gps0" / "data.csv"));
}

/// Normalized cross-correlation of two equally long samples.
double ncc(const std::vector<double>& a, const std::vector<double>& b) {
  const double n = static_cast<double>(a.size());
  double ma = 0, mb = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    ma += a[i];
    mb += b[i];
  }
  ma /= n;
  mb /= n;
  double sab = 0, saa = 0, sbb = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    sab += (a[i] - ma) * (b[i] - mb);
    saa += (a[i] - ma) * (a[i] - ma);
    sbb += (b[i] - mb) * (b[i] - mb);
  }
  return sab / std::sqrt(saa * sbb);
}

/// Correlation between an image of the files and the world's texture seen through the pose and
/// calibration read from the files: for a grid of pixels, the ray from the written calibration
/// and ground-truth pose is cast into the world and the texture shaded there.
double texture_correlation(const Scene& scene, const fs::path& mav0, std::size_t frame,
                           std::size_t pose_frame, const char* cam) {
  const auto cams = testing::read_csv(mav0 / "cam0" / "data.csv");
  const auto gt = testing::read_ground_truth(mav0);
  const auto calib = testing::read_camera_yaml(mav0 / cam / "sensor.yaml");
  const std::int64_t t_pose = std::stoll(cams.at(pose_frame)[0]);
  const auto row =
      std::find_if(gt.begin(), gt.end(), [&](const auto& g) { return g.t_ns == t_pose; });
  EXPECT_NE(row, gt.end());
  Eigen::Isometry3d T_wb = Eigen::Isometry3d::Identity();
  T_wb.linear() = row->q.toRotationMatrix();
  T_wb.translation() = row->p;
  const Eigen::Isometry3d T_wc = T_wb * calib.T_BS;
  const cv::Mat img =
      cv::imread((mav0 / cam / "data" / cams.at(frame)[1]).string(), cv::IMREAD_GRAYSCALE);
  std::vector<double> rendered, expected;
  for (int y = 4; y < img.rows - 4; y += 5) {
    for (int x = 4; x < img.cols - 4; x += 5) {
      const Eigen::Vector3d d_cam((x - calib.cx) / calib.fx, (y - calib.cy) / calib.fy, 1.0);
      const Eigen::Vector3d d = T_wc.linear() * d_cam.normalized();
      const Hit hit = scene.world.cast(T_wc.translation().cast<float>(), d.cast<float>());
      if (hit.box < 0) continue;
      const Eigen::Vector3f p = T_wc.translation().cast<float>() + hit.t * d.cast<float>();
      expected.push_back(
          scene.world.shade(hit.box, hit.face, p, hit.t / static_cast<float>(calib.fx)));
      rendered.push_back(img.at<std::uint8_t>(y, x));
    }
  }
  EXPECT_GT(rendered.size(), 500u);
  return ncc(rendered, expected);
}

TEST(SyntheticGen, ImagesShowTheWorldAtTheWrittenGroundTruthPoses) {
  for (const Scenario scenario : {Scenario::kIndoorKnown, Scenario::kOutdoorUnknown}) {
    SCOPED_TRACE(std::string(to_string(scenario)));
    TempDir dir("consistency");
    GenerateOptions o = small_options(scenario, dir.path() / "ds", 30);
    o.resolution = Resolution{376, 240};
    generate_dataset(o);
    const Scene scene = build_scene(scenario, o.seed);
    const fs::path mav0 = has_map_run(scenario) ? o.out / "loc" / "mav0" : o.out / "mav0";
    for (const char* cam : {"cam0", "cam1"}) {
      const double right_pose = texture_correlation(scene, mav0, 20, 20, cam);
      const double stale_pose = texture_correlation(scene, mav0, 20, 27, cam);
      std::printf(
          "[ figures ] %s %s: NCC image vs world at ground truth %.3f (pose of 7 frames later: "
          "%.3f)\n",
          std::string(to_string(scenario)).c_str(), cam, right_pose, stale_pose);
      EXPECT_GT(right_pose, 0.85);
      EXPECT_LT(stale_pose, right_pose - 0.2);
    }
  }
}

TEST(SyntheticGen, TheEurocReaderReadsTheOutput) {
  TempDir dir("reader");
  GenerateOptions o = small_options(Scenario::kOutdoorUnknown, dir.path() / "ds", 6);
  o.resolution = Resolution{320, 180};
  const GenerateSummary summary = generate_dataset(o);
  const auto dataset = datasets::open_dataset(o.out, datasets::DatasetFormat::kEuroc);
  ASSERT_EQ(dataset->frame_count(), 6u);
  EXPECT_EQ(dataset->imu().size(), 51u);
  EXPECT_EQ(dataset->ground_truth().size(), 51u);
  EXPECT_EQ(dataset->gps().size(), summary.runs[0].gps_fixes);
  EXPECT_EQ(dataset->frame_time(0), kStartTimeNs);
  const auto& calib = dataset->calibration();
  EXPECT_NEAR(calib.rectified.fx, summary.rig.fx, 1e-9);
  EXPECT_NEAR(calib.rectified.cx, summary.rig.cx, 1e-9);
  EXPECT_NEAR(calib.baseline_m, 0.54, 1e-9);
  EXPECT_LT((calib.T_body_left.matrix() - summary.rig.T_body_left.matrix()).norm(), 1e-9);
  const auto noise = dataset->imu_noise();
  ASSERT_TRUE(noise.has_value());
  EXPECT_DOUBLE_EQ(noise->accel_random_walk, 3.0e-3);
  // The turn-on bias the generator draws from, stated for the filter's prior.
  EXPECT_EQ(noise->gyro_bias_sigma, ImuModel{}.initial_gyro_bias_sigma);
  EXPECT_EQ(noise->accel_bias_sigma, ImuModel{}.initial_accel_bias_sigma);
  // Frames come back unchanged (already rectified: no remap).
  const datasets::StereoFrame f = dataset->load_frame(3);
  const auto cams = testing::read_csv(o.out / "mav0" / "cam0" / "data.csv");
  const cv::Mat left =
      cv::imread((o.out / "mav0" / "cam0" / "data" / cams[3][1]).string(), cv::IMREAD_GRAYSCALE);
  EXPECT_EQ(cv::norm(f.left, left, cv::NORM_INF), 0.0);
  const auto gt = testing::read_ground_truth(o.out / "mav0");
  EXPECT_LT((dataset->ground_truth()[10].T_world_body.translation() - gt[10].p).norm(), 1e-9);
}

}  // namespace
}  // namespace edx::synthetic
