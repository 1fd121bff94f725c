#include "workloads/backend/backend.hpp"

namespace edx::backend {

BackendCamera BackendCamera::from(const datasets::StereoCalibration& calibration) {
  BackendCamera camera;
  camera.width = calibration.rectified.width;
  camera.height = calibration.rectified.height;
  camera.fx = calibration.rectified.fx;
  camera.fy = calibration.rectified.fy;
  camera.cx = calibration.rectified.cx;
  camera.cy = calibration.rectified.cy;
  camera.baseline_m = calibration.baseline_m;
  camera.T_body_left = calibration.T_body_left;
  return camera;
}

}  // namespace edx::backend
