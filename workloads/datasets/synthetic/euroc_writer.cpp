#include "workloads/datasets/synthetic/euroc_writer.hpp"

#include <fmt/format.h>

#include <fstream>
#include <stdexcept>

#include "workloads/datasets/png_io.hpp"

namespace edx::synthetic {

namespace fs = std::filesystem;

namespace {

/// A YAML/CSV number: shortest round-trip representation, always with a decimal point or an
/// exponent so it reads as a real number; -0 printed as 0.
std::string real(double v) {
  std::string s = fmt::format("{}", v + 0.0);
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";
  return s;
}

/// Fixed 9-decimal format for data.csv values (nanometre / nano-radian resolution).
std::string fixed9(double v) {
  std::string s = fmt::format("{:.9f}", v);
  if (s == "-0.000000000") s = "0.000000000";
  return s;
}

std::string t_bs_block(const Eigen::Isometry3d& T) {
  const Eigen::Matrix4d M = T.matrix();
  std::string s = "T_BS:\n  cols: 4\n  rows: 4\n  data: [";
  for (int r = 0; r < 4; ++r) {
    if (r > 0) s += "         ";
    for (int c = 0; c < 4; ++c) {
      s += real(M(r, c));
      if (c < 3)
        s += ", ";
      else if (r < 3)
        s += ",";
    }
    s += r < 3 ? "\n" : "]\n";
  }
  return s;
}

void make_dir(const fs::path& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw std::runtime_error(dir.string() + ": cannot create directory: " + ec.message());
}

}  // namespace

void write_text_file(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw std::runtime_error(path.string() + ": cannot open for writing");
  out.write(text.data(), static_cast<std::streamsize>(text.size()));
  out.close();
  if (!out) throw std::runtime_error(path.string() + ": write failed");
}

EurocWriter::EurocWriter(fs::path mav0, const StereoRig& rig, double camera_rate_hz,
                         std::string comment)
    : mav0_(std::move(mav0)),
      rig_(rig),
      camera_rate_hz_(camera_rate_hz),
      comment_(std::move(comment)) {
  for (const char* sub : {"cam0/data", "cam1/data", "imu0", "state_groundtruth_estimate0"}) {
    make_dir(mav0_ / sub);
  }
}

void EurocWriter::add_frame(datasets::TimestampNs t_ns, const cv::Mat& left, const cv::Mat& right) {
  const std::string name = std::to_string(t_ns) + ".png";
  // libpng's SUB filter (each byte minus its left neighbour), zlib's fastest level and the
  // Huffman-only strategy, which skips the string matching that finds almost nothing in sensor
  // noise: the bytes cv::imwrite wrote with IMWRITE_PNG_STRATEGY_HUFFMAN_ONLY (png_io.hpp). Same
  // pixels as compression level 1 with libpng's adaptive filters, at about a third of the
  // encoding time, ~1/3 faster to decode, and files within a few per cent of its size
  // (docs/BENCH.md, "Issue 44 point 3, the demo's tracing").
  for (const auto& [cam, image] : {std::pair{"cam0", &left}, std::pair{"cam1", &right}}) {
    datasets::write_png_gray(mav0_ / cam / "data" / name, *image);
  }
  frames_.push_back(t_ns);
}

void EurocWriter::write_imu(const std::vector<datasets::ImuSample>& samples,
                            const ImuModel& model) {
  std::string csv =
      "#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1],"
      "a_RS_S_x [m s^-2],a_RS_S_y [m s^-2],a_RS_S_z [m s^-2]\n";
  csv.reserve(samples.size() * 96);
  for (const auto& s : samples) {
    csv += fmt::format("{},{},{},{},{},{},{}\n", s.t_ns, fixed9(s.gyro_rad_s.x()),
                       fixed9(s.gyro_rad_s.y()), fixed9(s.gyro_rad_s.z()), fixed9(s.accel_m_s2.x()),
                       fixed9(s.accel_m_s2.y()), fixed9(s.accel_m_s2.z()));
  }
  write_text_file(mav0_ / "imu0" / "data.csv", csv);
  std::string yaml =
      "%YAML:1.0\n"
      "#Default imu sensor yaml file\n"
      "sensor_type: imu\n"
      "comment: edx synthetic IMU (body frame = IMU frame)\n"
      "\n"
      "# Sensor extrinsics wrt. the body-frame.\n" +
      t_bs_block(Eigen::Isometry3d::Identity()) + "rate_hz: " + fmt::format("{}", model.rate_hz) +
      "\n\n# inertial sensor noise model parameters (static)\n";
  const double zero_if_ideal = model.noise_free ? 0.0 : 1.0;
  yaml += "gyroscope_noise_density: " + real(zero_if_ideal * model.gyro_noise_density) +
          "     # [ rad / s / sqrt(Hz) ]   ( gyro \"white noise\" )\n";
  yaml += "gyroscope_random_walk: " + real(zero_if_ideal * model.gyro_random_walk) +
          "       # [ rad / s^2 / sqrt(Hz) ] ( gyro bias diffusion )\n";
  yaml += "accelerometer_noise_density: " + real(zero_if_ideal * model.accel_noise_density) +
          "  # [ m / s^2 / sqrt(Hz) ]   ( accel \"white noise\" )\n";
  yaml += "accelerometer_random_walk: " + real(zero_if_ideal * model.accel_random_walk) +
          "    # [ m / s^3 / sqrt(Hz) ].  ( accel bias diffusion )\n";
  // The turn-on bias the generator draws from (an ideal IMU has none; the reader wants > 0).
  if (!model.noise_free && model.initial_gyro_bias_sigma > 0) {
    yaml += "gyroscope_bias_sigma: " + real(model.initial_gyro_bias_sigma) +
            "        # [ rad / s ] ( turn-on bias, 1 sigma per axis; edx key )\n";
  }
  if (!model.noise_free && model.initial_accel_bias_sigma > 0) {
    yaml += "accelerometer_bias_sigma: " + real(model.initial_accel_bias_sigma) +
            "    # [ m / s^2 ] ( turn-on bias, 1 sigma per axis; edx key )\n";
  }
  write_text_file(mav0_ / "imu0" / "sensor.yaml", yaml);
}

void EurocWriter::write_ground_truth(const std::vector<GroundTruthState>& states) {
  std::string csv =
      "#timestamp, p_RS_R_x [m], p_RS_R_y [m], p_RS_R_z [m], q_RS_w [], q_RS_x [], q_RS_y [], "
      "q_RS_z [], v_RS_R_x [m s^-1], v_RS_R_y [m s^-1], v_RS_R_z [m s^-1], "
      "b_w_RS_S_x [rad s^-1], b_w_RS_S_y [rad s^-1], b_w_RS_S_z [rad s^-1], "
      "b_a_RS_S_x [m s^-2], b_a_RS_S_y [m s^-2], b_a_RS_S_z [m s^-2]\n";
  csv.reserve(states.size() * 200);
  for (const auto& s : states) {
    csv += fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n", s.t_ns,
                       fixed9(s.position.x()), fixed9(s.position.y()), fixed9(s.position.z()),
                       fixed9(s.orientation.w()), fixed9(s.orientation.x()),
                       fixed9(s.orientation.y()), fixed9(s.orientation.z()), fixed9(s.velocity.x()),
                       fixed9(s.velocity.y()), fixed9(s.velocity.z()), fixed9(s.gyro_bias.x()),
                       fixed9(s.gyro_bias.y()), fixed9(s.gyro_bias.z()), fixed9(s.accel_bias.x()),
                       fixed9(s.accel_bias.y()), fixed9(s.accel_bias.z()));
  }
  write_text_file(mav0_ / "state_groundtruth_estimate0" / "data.csv", csv);
  write_text_file(mav0_ / "state_groundtruth_estimate0" / "sensor.yaml",
                  "%YAML:1.0\n"
                  "# General sensor definitions.\n"
                  "sensor_type: visual-inertial\n"
                  "comment: edx synthetic ground truth: the exact trajectory of the body (IMU) "
                  "frame with the true IMU biases.\n"
                  "\n"
                  "# Sensor extrinsics wrt. the body-frame. This is the transformation of the\n"
                  "# tracking prima to the body frame.\n" +
                      t_bs_block(Eigen::Isometry3d::Identity()));
}

void EurocWriter::write_gps(const std::vector<datasets::GpsFix>& fixes, const GpsModel& model) {
  make_dir(mav0_ / "gps0");
  std::string csv = "#timestamp [ns],p_x [m],p_y [m],p_z [m],sigma [m]\n";
  for (const auto& f : fixes) {
    csv += fmt::format("{},{},{},{},{}\n", f.t_ns, fixed9(f.position_m.x()),
                       fixed9(f.position_m.y()), fixed9(f.position_m.z()), fixed9(f.sigma_m));
  }
  write_text_file(mav0_ / "gps0" / "data.csv", csv);
  write_text_file(mav0_ / "gps0" / "sensor.yaml",
                  "%YAML:1.0\n"
                  "# General sensor definitions.\n"
                  "sensor_type: gps\n"
                  "comment: edx synthetic GPS: body position in the ground-truth world frame "
                  "plus white noise, with drop-outs.\n"
                  "\n"
                  "# Sensor extrinsics wrt. the body-frame.\n" +
                      t_bs_block(Eigen::Isometry3d::Identity()) + "rate_hz: " +
                      fmt::format("{}", model.rate_hz) + "\n" + "sigma_m: " + real(model.sigma_m) +
                      "\n" + "dropout_rate_per_min: " + real(model.dropout_rate_per_min) + "\n" +
                      "dropout_mean_s: " + real(model.dropout_mean_s) + "\n");
}

void EurocWriter::finish() {
  std::string list = "#timestamp [ns],filename\n";
  for (const auto t : frames_) list += fmt::format("{},{}.png\n", t, t);
  const std::array<std::pair<const char*, Eigen::Isometry3d>, 2> cams = {
      std::pair{"cam0", rig_.T_body_left}, std::pair{"cam1", rig_.T_body_right()}};
  for (const auto& [cam, T] : cams) {
    write_text_file(mav0_ / cam / "data.csv", list);
    const std::string side = std::string(cam) == "cam0" ? "left" : "right";
    const std::string yaml =
        "%YAML:1.0\n"
        "# General sensor definitions.\n"
        "sensor_type: camera\n"
        "comment: edx synthetic " +
        std::string(cam) + " (" + side + ", rectified, " + std::string(to_string(rig_.kind)) +
        " rig, baseline " + real(rig_.baseline_m) +
        " m)\n"
        "\n"
        "# Sensor extrinsics wrt. the body-frame.\n" +
        t_bs_block(T) +
        "\n"
        "# Camera specific definitions.\n"
        "rate_hz: " +
        fmt::format("{}", camera_rate_hz_) + "\n" +
        fmt::format("resolution: [{}, {}]\n", rig_.width, rig_.height) +
        "camera_model: pinhole\n"
        "intrinsics: [" +
        real(rig_.fx) + ", " + real(rig_.fy) + ", " + real(rig_.cx) + ", " + real(rig_.cy) +
        "] #fu, fv, cu, cv\n"
        "distortion_model: radial-tangential\n"
        "distortion_coefficients: [0.0, 0.0, 0.0, 0.0]\n";
    write_text_file(mav0_ / cam / "sensor.yaml", yaml);
  }
  write_text_file(mav0_ / "body.yaml", "%YAML:1.0\ncomment: " + comment_ + "\n");
}

}  // namespace edx::synthetic
