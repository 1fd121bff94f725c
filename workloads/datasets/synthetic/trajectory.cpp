#include "workloads/datasets/synthetic/trajectory.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "workloads/datasets/synthetic/random.hpp"

namespace edx::synthetic {

CubicBSpline::CubicBSpline(std::vector<Eigen::Vector3d> control_points, double t0, double dt)
    : points_(std::move(control_points)), t0_(t0), dt_(dt) {
  if (points_.size() < 4)
    throw std::runtime_error("cubic B-spline: needs at least 4 control points");
  if (!(dt_ > 0)) throw std::runtime_error("cubic B-spline: knot spacing must be positive");
}

CubicBSpline::Sample CubicBSpline::evaluate(double t) const {
  const double segments = static_cast<double>(points_.size() - 3);
  const double s = std::clamp((t - t0_) / dt_, 0.0, segments);
  const std::size_t i = std::min(static_cast<std::size_t>(s), points_.size() - 4);
  const double u = s - static_cast<double>(i);
  const double u2 = u * u, u3 = u2 * u, w = 1.0 - u;
  const std::array<double, 4> b = {w * w * w / 6.0, (3 * u3 - 6 * u2 + 4) / 6.0,
                                   (-3 * u3 + 3 * u2 + 3 * u + 1) / 6.0, u3 / 6.0};
  const std::array<double, 4> db = {-w * w / 2.0, (3 * u2 - 4 * u) / 2.0,
                                    (-3 * u2 + 2 * u + 1) / 2.0, u2 / 2.0};
  const std::array<double, 4> ddb = {w, 3 * u - 2, -3 * u + 1, u};
  Sample out{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  for (std::size_t k = 0; k < 4; ++k) {
    const Eigen::Vector3d& p = points_[i + k];
    out.position += b[k] * p;
    out.velocity += db[k] * p;
    out.acceleration += ddb[k] * p;
  }
  out.velocity /= dt_;
  out.acceleration /= dt_ * dt_;
  return out;
}

double Wobble::value(double t) const {
  double v = 0;
  for (std::size_t k = 0; k < amplitude.size(); ++k)
    v += amplitude[k] * std::sin(omega[k] * t + phase[k]);
  return v;
}

double Wobble::rate(double t) const {
  double v = 0;
  for (std::size_t k = 0; k < amplitude.size(); ++k) {
    v += amplitude[k] * omega[k] * std::cos(omega[k] * t + phase[k]);
  }
  return v;
}

Eigen::Isometry3d BodyState::T_world_body() const {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R_world_body;
  T.translation() = position;
  return T;
}

Eigen::Vector3d euler_zyx_rates_to_body(double pitch, double roll, double yaw_rate,
                                        double pitch_rate, double roll_rate) {
  const double sp = std::sin(pitch), cp = std::cos(pitch);
  const double sr = std::sin(roll), cr = std::cos(roll);
  return {roll_rate - yaw_rate * sp, pitch_rate * cr + yaw_rate * cp * sr,
          -pitch_rate * sr + yaw_rate * cp * cr};
}

Trajectory::Trajectory(CubicBSpline spline, double time_offset, Wobble yaw, Wobble pitch,
                       Wobble roll)
    : spline_(std::move(spline)),
      time_offset_(time_offset),
      yaw_(yaw),
      pitch_(pitch),
      roll_(roll) {}

BodyState Trajectory::at(double t) const {
  const CubicBSpline::Sample s = spline_.evaluate(t + time_offset_);
  BodyState state;
  state.t = t;
  state.position = s.position;
  state.velocity = s.velocity;
  state.acceleration = s.acceleration;
  // Heading of the horizontal velocity and its rate d/dt atan2(vy, vx) = (vx ay - vy ax)/|v_xy|^2.
  const double vx = s.velocity.x(), vy = s.velocity.y();
  const double speed_sq = vx * vx + vy * vy;
  const double heading = std::atan2(vy, vx);
  const double heading_rate =
      speed_sq > 1e-9 ? (vx * s.acceleration.y() - vy * s.acceleration.x()) / speed_sq : 0.0;
  const double yaw = heading + yaw_.value(t);
  const double pitch = pitch_.value(t);
  const double roll = roll_.value(t);
  state.R_world_body = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                        Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                        Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                           .toRotationMatrix();
  state.omega_body = euler_zyx_rates_to_body(pitch, roll, heading_rate + yaw_.rate(t),
                                             pitch_.rate(t), roll_.rate(t));
  return state;
}

namespace {

/// A dense sample of the planned path (before the B-spline fit).
struct PathPoint {
  Eigen::Vector2d xy;
  double ds = 0;  ///< distance from the previous sample
  bool turning = false;
  double cruise = 0;  ///< speed limit of the corridor it lies on
};

constexpr double kPathStep = 0.25;  // m between dense path samples

Eigen::Vector2d right_of(const Eigen::Vector2d& d) { return {d.y(), -d.x()}; }

/// Random walk on the lane graph, never turning back unless at a dead end.
std::vector<int> random_route(const LaneGraph& g, int start, int first_next, double min_length,
                              Rng& rng) {
  std::vector<int> route = {start};
  int prev = -1, cur = start;
  double length = 0;
  while (length < min_length) {
    const auto& nb = g.neighbours[static_cast<std::size_t>(cur)];
    if (nb.empty()) throw std::runtime_error("synthetic route: lane graph node without neighbours");
    int next;
    if (route.size() == 1 && first_next >= 0) {
      next = first_next;
    } else {
      std::vector<int> options;
      for (const int n : nb) {
        if (n != prev) options.push_back(n);
      }
      if (options.empty()) options = nb;
      next = options[static_cast<std::size_t>(
          uniform_int(rng, 0, static_cast<int>(options.size()) - 1))];
    }
    length +=
        (g.nodes[static_cast<std::size_t>(next)] - g.nodes[static_cast<std::size_t>(cur)]).norm();
    route.push_back(next);
    prev = cur;
    cur = next;
  }
  return route;
}

/// Appends samples of the segment a->b (excluding a) every ~kPathStep.
void add_straight(std::vector<PathPoint>& path, const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                  double cruise) {
  const double len = (b - a).norm();
  const int n = std::max(1, static_cast<int>(std::ceil(len / kPathStep)));
  for (int k = 1; k <= n; ++k) {
    PathPoint p;
    p.xy = a + (b - a) * (static_cast<double>(k) / n);
    p.ds = len / n;
    p.cruise = cruise;
    path.push_back(p);
  }
}

/// Dense path along the route: lane-offset centre lines with corners rounded by circular fillets.
std::vector<PathPoint> route_path(const LaneGraph& g, const std::vector<int>& route,
                                  const MotionLimits& limits, Rng& rng) {
  const std::size_t n = route.size();
  std::vector<Eigen::Vector2d> nodes, dirs;
  for (const int r : route) nodes.push_back(g.nodes[static_cast<std::size_t>(r)]);
  for (std::size_t i = 0; i + 1 < n; ++i) dirs.push_back((nodes[i + 1] - nodes[i]).normalized());
  // Corners of the offset polyline: intersections of consecutive offset lines.
  const double off = limits.lane_offset_m;
  std::vector<Eigen::Vector2d> corners(n);
  corners[0] = nodes[0] + off * right_of(dirs[0]);
  corners[n - 1] = nodes[n - 1] + off * right_of(dirs[n - 2]);
  for (std::size_t i = 1; i + 1 < n; ++i) {
    const Eigen::Vector2d &d1 = dirs[i - 1], &d2 = dirs[i];
    if (d1.dot(d2) < -0.999) throw std::runtime_error("synthetic route: U-turn in route");
    if (d1.dot(d2) > 0.999) {
      corners[i] = nodes[i] + off * right_of(d2);
      continue;
    }
    // nodes[i] + off r1 + a d1 = nodes[i] + off r2 + b d2  ->  [d1 -d2] [a b]^T = off (r2 - r1)
    Eigen::Matrix2d A;
    A << d1, -d2;
    const Eigen::Vector2d ab = A.colPivHouseholderQr().solve(off * (right_of(d2) - right_of(d1)));
    corners[i] = nodes[i] + off * right_of(d1) + ab.x() * d1;
  }
  std::vector<double> cruise(n - 1);
  for (auto& c : cruise) c = uniform(rng, limits.cruise_speed_min, limits.cruise_speed_max);

  std::vector<PathPoint> path;
  PathPoint first;
  first.xy = corners[0];
  first.cruise = cruise[0];
  path.push_back(first);
  Eigen::Vector2d cursor = corners[0];
  for (std::size_t i = 1; i + 1 < n; ++i) {
    const Eigen::Vector2d c = corners[i];
    const Eigen::Vector2d d1 = (c - corners[i - 1]).normalized();
    const Eigen::Vector2d d2 = (corners[i + 1] - c).normalized();
    const double cos_turn = std::clamp(d1.dot(d2), -1.0, 1.0);
    const double turn = std::acos(cos_turn);
    if (turn < 1e-3) continue;  // straight through
    // Fillet of radius R: tangent points at distance L = R tan(turn/2) from the corner.
    const double max_l = 0.45 * std::min((c - corners[i - 1]).norm(), (corners[i + 1] - c).norm());
    const double l = std::min(limits.turn_radius_m * std::tan(turn / 2), max_l);
    const double radius = l / std::tan(turn / 2);
    const Eigen::Vector2d t1 = c - l * d1, t2 = c + l * d2;
    add_straight(path, cursor, t1, cruise[i - 1]);
    const double side = d1.x() * d2.y() - d1.y() * d2.x() > 0 ? 1.0 : -1.0;  // +1: left turn
    const Eigen::Vector2d normal = side * Eigen::Vector2d(-d1.y(), d1.x());
    const Eigen::Vector2d centre = t1 + radius * normal;
    const Eigen::Vector2d r0 = t1 - centre;
    const double arc = radius * turn;
    const int steps = std::max(2, static_cast<int>(std::ceil(arc / kPathStep)));
    for (int k = 1; k <= steps; ++k) {
      const double a = side * turn * k / steps;
      const Eigen::Vector2d rk(std::cos(a) * r0.x() - std::sin(a) * r0.y(),
                               std::sin(a) * r0.x() + std::cos(a) * r0.y());
      PathPoint p;
      p.xy = centre + rk;
      p.ds = arc / steps;
      p.turning = true;
      p.cruise = limits.turn_speed;
      path.push_back(p);
    }
    cursor = t2;
  }
  add_straight(path, cursor, corners[n - 1], cruise[n - 2]);
  return path;
}

/// Sum of three sinusoids of wavelengths in [lambda_min, lambda_max], normalised to |g| <= 1.
struct SmoothField {
  std::array<double, 3> weight{}, k{}, phase{};
  SmoothField(Rng& rng, double lambda_min, double lambda_max) {
    double total = 0;
    for (std::size_t i = 0; i < 3; ++i) {
      weight[i] = uniform(rng, 0.5, 1.0);
      k[i] = 6.283185307179586 / uniform(rng, lambda_min, lambda_max);
      phase[i] = uniform(rng, 0, 6.283185307179586);
      total += weight[i];
    }
    for (auto& w : weight) w /= total;
  }
  double operator()(double s) const {
    double v = 0;
    for (std::size_t i = 0; i < 3; ++i) v += weight[i] * std::sin(k[i] * s + phase[i]);
    return v;
  }
};

Wobble make_wobble(Rng& rng, double amplitude, double period_min, double period_max) {
  Wobble w;
  for (std::size_t i = 0; i < 3; ++i) {
    w.amplitude[i] = amplitude / 3.0 * uniform(rng, 0.6, 1.0);
    w.omega[i] = 6.283185307179586 / uniform(rng, period_min, period_max);
    w.phase[i] = uniform(rng, 0, 6.283185307179586);
  }
  return w;
}

/// One attempt: route, timed path, B-spline fit, attitude.
PlannedTrajectory plan_once(const Scene& scene, double duration_s, Rng& rng,
                            const Revisit* revisit) {
  MotionLimits limits = scene.motion;
  const LaneGraph& g = scene.lanes;
  const bool drone = limits.style == MotionStyle::kDrone;
  const double knot_dt = drone ? 0.5 : 0.25;
  int start = uniform_int(rng, 0, static_cast<int>(g.nodes.size()) - 1);
  int first_next = -1;
  const bool retraverse = revisit != nullptr && revisit->mode == RevisitMode::kRetraverse;
  if (retraverse) {
    // Same lanes in the same direction, offset sideways and at other speeds.
    limits.lane_offset_m += revisit->lateral_offset_m;
    limits.cruise_speed_min *= revisit->speed_scale;
    limits.cruise_speed_max *= revisit->speed_scale;
    limits.turn_speed *= revisit->speed_scale;
  } else if (revisit != nullptr) {
    // Start where the earlier run passed and leave in a direction it did not take there.
    const std::vector<int>& earlier = revisit->route;
    const std::size_t idx = earlier.size() >= 3 ? earlier.size() / 3 : 0;
    start = earlier[idx];
    const int earlier_prev = idx > 0 ? earlier[idx - 1] : -1;
    const int earlier_next = earlier[idx + 1];
    std::vector<int> options;
    for (const int nb : g.neighbours[static_cast<std::size_t>(start)]) {
      if (nb != earlier_next && nb != earlier_prev) options.push_back(nb);
    }
    if (options.empty()) options.push_back(earlier_prev >= 0 ? earlier_prev : earlier_next);
    first_next = options[static_cast<std::size_t>(
        uniform_int(rng, 0, static_cast<int>(options.size()) - 1))];
  }
  const double min_length =
      limits.cruise_speed_max * (duration_s + 6 * knot_dt) + 4 * limits.turn_radius_m + 10.0;
  std::vector<int> route;
  if (retraverse) {
    // The earlier route, continued by a random walk (no U-turn) if it is too short here.
    route = revisit->route;
    double length = 0;
    for (std::size_t i = 1; i < route.size(); ++i) {
      length += (g.nodes[static_cast<std::size_t>(route[i])] -
                 g.nodes[static_cast<std::size_t>(route[i - 1])])
                    .norm();
    }
    if (length < min_length) {
      const int prev = route[route.size() - 2];
      std::vector<int> options;
      for (const int nb : g.neighbours[static_cast<std::size_t>(route.back())]) {
        if (nb != prev) options.push_back(nb);
      }
      if (options.empty()) options.push_back(prev);
      const int next = options[static_cast<std::size_t>(
          uniform_int(rng, 0, static_cast<int>(options.size()) - 1))];
      const std::vector<int> tail = random_route(g, route.back(), next, min_length - length, rng);
      route.insert(route.end(), tail.begin() + 1, tail.end());
    }
  } else {
    route = random_route(g, start, first_next, min_length, rng);
  }
  std::vector<PathPoint> path = route_path(g, route, limits, rng);

  // Speed profile: corridor limits, then |dv/ds| bounded by a_max (v dv = a ds), both ways.
  const std::size_t n = path.size();
  std::vector<double> v(n);
  for (std::size_t i = 0; i < n; ++i) v[i] = path[i].cruise;
  for (std::size_t i = 1; i < n; ++i) {
    v[i] = std::min(v[i], std::sqrt(v[i - 1] * v[i - 1] + 2 * limits.max_accel * path[i].ds));
  }
  for (std::size_t i = n - 1; i-- > 0;) {
    v[i] = std::min(v[i], std::sqrt(v[i + 1] * v[i + 1] + 2 * limits.max_accel * path[i + 1].ds));
  }
  std::vector<double> time(n, 0.0), arclen(n, 0.0);
  for (std::size_t i = 1; i < n; ++i) {
    time[i] = time[i - 1] + 2 * path[i].ds / (v[i - 1] + v[i]);
    arclen[i] = arclen[i - 1] + path[i].ds;
  }
  // Distance along the path to the nearest turning sample (drones stop wandering in turns).
  std::vector<double> to_turn(n, 1e9);
  for (std::size_t i = 0; i < n; ++i) {
    if (path[i].turning)
      to_turn[i] = 0;
    else if (i > 0)
      to_turn[i] = to_turn[i - 1] + path[i].ds;
  }
  for (std::size_t i = n - 1; i-- > 0;)
    to_turn[i] = std::min(to_turn[i], to_turn[i + 1] + path[i + 1].ds);

  const SmoothField lateral(rng, 6.0, 18.0);
  const SmoothField height(rng, 14.0, 30.0);
  const double mid_h = 0.5 * (limits.min_height_m + limits.max_height_m);
  const double half_h = 0.5 * (limits.max_height_m - limits.min_height_m);
  std::vector<Eigen::Vector3d> points(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t a = i == 0 ? 0 : i - 1, b = std::min(i + 1, n - 1);
    const Eigen::Vector2d tangent = (path[b].xy - path[a].xy).normalized();
    const double fade = std::clamp(to_turn[i] / 4.0, 0.0, 1.0);
    const Eigen::Vector2d xy =
        path[i].xy + limits.lateral_wander_m * fade * lateral(arclen[i]) * right_of(tangent);
    points[i] = Eigen::Vector3d(xy.x(), xy.y(), mid_h + half_h * height(arclen[i]));
  }

  // Control points: the timed path sampled every knot_dt (linear interpolation in time).
  const int knots_needed = static_cast<int>(std::ceil(duration_s / knot_dt)) + 3;
  if (time.back() < (knots_needed + 1) * knot_dt) {
    throw std::logic_error("synthetic route: path shorter than planned");
  }
  std::vector<Eigen::Vector3d> control;
  std::size_t j = 0;
  for (int k = 0; k <= knots_needed; ++k) {
    const double tk = k * knot_dt;
    while (j + 1 < n && time[j + 1] < tk) ++j;
    const double span = time[j + 1] - time[j];
    const double a = span > 0 ? std::clamp((tk - time[j]) / span, 0.0, 1.0) : 0.0;
    control.push_back(points[j] + a * (points[j + 1] - points[j]));
  }
  CubicBSpline spline(std::move(control), 0.0, knot_dt);
  const Wobble yaw = drone ? make_wobble(rng, 0.15, 2.5, 7.0) : make_wobble(rng, 0.004, 1.0, 3.0);
  const Wobble pitch = drone ? make_wobble(rng, 0.06, 1.5, 4.0) : make_wobble(rng, 0.008, 0.8, 2.5);
  const Wobble roll = drone ? make_wobble(rng, 0.06, 1.5, 4.0) : make_wobble(rng, 0.01, 0.8, 2.5);
  return PlannedTrajectory{Trajectory(std::move(spline), 0.0, yaw, pitch, roll), route, 1};
}

/// True when the body origin and all body points keep the clearance over the whole duration.
bool keeps_clearance(const Scene& scene, const Trajectory& traj, double duration_s,
                     const std::vector<Eigen::Vector3d>& body_points) {
  const double step = 0.05;
  const int samples = static_cast<int>(std::ceil(duration_s / step));
  for (int k = 0; k <= samples; ++k) {
    const BodyState s = traj.at(std::min(k * step, duration_s));
    const Eigen::Isometry3d T = s.T_world_body();
    if (scene.world.distance_to_geometry(s.position) < scene.motion.clearance_m) return false;
    for (const auto& p : body_points) {
      if (scene.world.distance_to_geometry(T * p) < scene.motion.clearance_m) return false;
    }
  }
  return true;
}

}  // namespace

PlannedTrajectory plan_trajectory(const Scene& scene, double duration_s, std::uint64_t seed,
                                  const std::vector<Eigen::Vector3d>& body_points,
                                  const Revisit* revisit) {
  if (!(duration_s > 0))
    throw std::runtime_error("synthetic trajectory: duration must be positive");
  if (revisit != nullptr) {
    if (revisit->route.size() < 2)
      throw std::runtime_error("synthetic trajectory: revisit route needs at least 2 nodes");
    if (!(std::abs(revisit->lateral_offset_m) <= 2.0))
      throw std::runtime_error("synthetic trajectory: revisit lateral offset must be in [-2, 2] m");
    if (!(revisit->speed_scale >= 0.25 && revisit->speed_scale <= 2.0))
      throw std::runtime_error("synthetic trajectory: revisit speed scale must be in [0.25, 2]");
  }
  if (scene.lanes.nodes.size() < 2) throw std::runtime_error("synthetic trajectory: no lanes");
  constexpr int kAttempts = 20;
  for (int attempt = 0; attempt < kAttempts; ++attempt) {
    Rng rng(derive_seed(seed, "route", static_cast<std::uint64_t>(attempt)));
    PlannedTrajectory planned = plan_once(scene, duration_s, rng, revisit);
    if (keeps_clearance(scene, planned.trajectory, duration_s, body_points)) {
      planned.attempts = attempt + 1;
      return planned;
    }
  }
  throw std::runtime_error("synthetic trajectory: no collision-free route found in " +
                           std::to_string(kAttempts) + " attempts");
}

}  // namespace edx::synthetic
