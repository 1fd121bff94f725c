#include "workloads/backend/slam/window.hpp"

#include <stdexcept>
#include <string>

#include "workloads/backend/so3.hpp"

namespace edx::backend::slam {

Eigen::Isometry3d KeyframeState::T_world_body() const {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R;
  T.translation() = p;
  return T;
}

KeyframeState KeyframeState::navigation_state() const {
  KeyframeState x;
  x.id = id;
  x.t_ns = t_ns;
  x.frame_index = frame_index;
  x.R = R;
  x.p = p;
  x.v = v;
  x.ba = ba;
  x.bg = bg;
  return x;
}

void KeyframeState::apply_increment(const Eigen::VectorXd& dx, int dim) {
  p += dx.segment<3>(0);
  R = R * so3_exp(dx.segment<3>(3));
  R = Eigen::Quaterniond(R).normalized().toRotationMatrix();
  if (dim == 15) {
    v += dx.segment<3>(6);
    ba += dx.segment<3>(9);
    bg += dx.segment<3>(12);
  }
}

Eigen::VectorXd KeyframeState::difference(const KeyframeState& x0, int dim) const {
  Eigen::VectorXd dx(dim);
  dx.segment<3>(0) = p - x0.p;
  dx.segment<3>(3) = so3_log(x0.R.transpose() * R);
  if (dim == 15) {
    dx.segment<3>(6) = v - x0.v;
    dx.segment<3>(9) = ba - x0.ba;
    dx.segment<3>(12) = bg - x0.bg;
  }
  return dx;
}

int Landmark::inlier_count() const {
  int n = 0;
  for (const Observation& o : observations) n += o.inlier ? 1 : 0;
  return n;
}

int Window::slot(std::int64_t keyframe_id) const {
  for (std::size_t i = 0; i < keyframes.size(); ++i) {
    if (keyframes[i].id == keyframe_id) return static_cast<int>(i);
  }
  return -1;
}

const KeyframeState& Window::keyframe(std::int64_t keyframe_id) const {
  const int s = slot(keyframe_id);
  if (s < 0) throw std::logic_error("slam window: no keyframe " + std::to_string(keyframe_id));
  return keyframes[static_cast<std::size_t>(s)];
}

Eigen::VectorXd Window::prior_difference() const {
  const int d = state_dim;
  const int n = static_cast<int>(prior.keyframe_ids.size()) * d;
  Eigen::VectorXd dx(n + (prior.has_offset ? 1 : 0));
  for (std::size_t k = 0; k < prior.keyframe_ids.size(); ++k) {
    dx.segment(static_cast<int>(k) * d, d) =
        keyframe(prior.keyframe_ids[k]).difference(prior.linearization_points[k], d);
  }
  if (prior.has_offset) dx(n) = disparity_offset_px - prior.offset_linearization_px;
  return dx;
}

Eigen::Vector3d Window::landmark_world(const Landmark& landmark) const {
  const KeyframeState& a = keyframe(landmark.anchor_id);
  const Eigen::Vector3d p_body = camera.T_body_left * (landmark.bearing / landmark.inverse_depth);
  return a.R * p_body + a.p;
}

}  // namespace edx::backend::slam
