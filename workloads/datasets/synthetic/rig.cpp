#include "workloads/datasets/synthetic/rig.hpp"

#include <stdexcept>
#include <string>

#include "workloads/datasets/dataset.hpp"

namespace edx::synthetic {

Resolution parse_resolution(std::string_view text) {
  const cv::Size size = datasets::parse_resolution(text);  // "WxH" syntax, one parser in edx
  if (size.width < 32 || size.height < 32 || size.width > 8192 || size.height > 8192) {
    throw std::runtime_error("resolution '" + std::string(text) +
                             "': width and height must be in [32, 8192]");
  }
  return {size.width, size.height};
}

RigKind parse_rig(std::string_view text) {
  if (text == "euroc") return RigKind::kEuroc;
  if (text == "car") return RigKind::kCar;
  throw std::runtime_error("rig '" + std::string(text) + "': expected euroc or car");
}

std::string_view to_string(RigKind kind) { return kind == RigKind::kEuroc ? "euroc" : "car"; }

Resolution native_resolution(RigKind kind) {
  return kind == RigKind::kEuroc ? Resolution{752, 480} : Resolution{1280, 720};
}

Eigen::Isometry3d StereoRig::T_body_right() const {
  return T_body_left * Eigen::Translation3d(baseline_m, 0, 0);
}

StereoRig make_rig(RigKind kind, Resolution resolution) {
  if (resolution.width < 32 || resolution.height < 32 || resolution.width > 8192 ||
      resolution.height > 8192) {
    throw std::runtime_error("resolution " + std::to_string(resolution.width) + "x" +
                             std::to_string(resolution.height) + " outside [32, 8192]");
  }
  const Resolution native = native_resolution(kind);
  StereoRig rig;
  rig.kind = kind;
  rig.width = resolution.width;
  rig.height = resolution.height;
  // Camera axes in the body frame (body: x forward, y left, z up; camera: x right, y down,
  // z forward): columns are the camera axes.
  Eigen::Matrix3d R_body_cam;
  R_body_cam << 0, 0, 1,  //
      -1, 0, 0,           //
      0, -1, 0;
  double f_native, cx_native, cy_native;
  if (kind == RigKind::kEuroc) {
    f_native = 458.654;
    cx_native = 367.215;
    cy_native = 248.375;
    rig.baseline_m = 0.11;
    rig.T_body_left.linear() = R_body_cam;
    rig.T_body_left.translation() = Eigen::Vector3d(0.06, 0.055, 0.01);
  } else {
    f_native = 700.0;
    cx_native = 640.0;
    cy_native = 360.0;
    rig.baseline_m = 0.54;
    rig.T_body_left.linear() = R_body_cam;
    rig.T_body_left.translation() = Eigen::Vector3d(1.2, 0.27, 0.75);
  }
  const double sx = static_cast<double>(resolution.width) / native.width;
  const double sy = static_cast<double>(resolution.height) / native.height;
  // Pixel-centre convention (as cv::resize): c' = (c + 0.5) s - 0.5.
  rig.fx = rig.fy = f_native * sx;
  rig.cx = (cx_native + 0.5) * sx - 0.5;
  rig.cy = (cy_native + 0.5) * sy - 0.5;
  return rig;
}

}  // namespace edx::synthetic
