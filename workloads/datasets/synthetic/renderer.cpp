#include "workloads/datasets/synthetic/renderer.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

#include "common/parallel.hpp"

namespace edx::synthetic {

namespace {
constexpr float kNearPlane = 0.01f;  // m; boxes are clipped here before projection
}

Renderer::Renderer(const World& world, int threads)
    : world_(world), threads_(std::max(1, threads)) {}

void Renderer::prepare_directions(ViewState& view, const PinholeCamera& camera) const {
  if (view.camera == camera && !view.dirs.empty()) return;
  if (camera.width <= 0 || camera.height <= 0 || !(camera.fx > 0) || !(camera.fy > 0)) {
    throw std::runtime_error("renderer: invalid camera");
  }
  view.camera = camera;
  view.dirs.resize(static_cast<std::size_t>(camera.width) * camera.height * 4);
  for (int y = 0; y < camera.height; ++y) {
    for (int x = 0; x < camera.width; ++x) {
      const double dx = (x - camera.cx) / camera.fx;
      const double dy = (y - camera.cy) / camera.fy;
      const double inv_norm = 1.0 / std::sqrt(dx * dx + dy * dy + 1.0);
      float* d = &view.dirs[(static_cast<std::size_t>(y) * camera.width + x) * 4];
      d[0] = static_cast<float>(dx * inv_norm);
      d[1] = static_cast<float>(dy * inv_norm);
      d[2] = static_cast<float>(inv_norm);
      d[3] = static_cast<float>(inv_norm / camera.fx);  // angular size of the pixel, rad
    }
  }
  view.tiles_x = (camera.width + kTile - 1) / kTile;
  view.tiles_y = (camera.height + kTile - 1) / kTile;
}

void Renderer::bin_boxes(ViewState& view, const RenderView& rv) const {
  const PinholeCamera& cam = rv.camera;
  view.R_world_camera = rv.T_world_camera.linear().cast<float>();
  view.origin = rv.T_world_camera.translation().cast<float>();
  const Eigen::Matrix3f R_cw = view.R_world_camera.transpose();
  const Eigen::Vector3f o = view.origin;

  struct Candidate {
    float d_near;
    int box;
    int tx0, ty0, tx1, ty1;
  };
  std::vector<Candidate> candidates;
  const auto& boxes = world_.boxes();
  candidates.reserve(boxes.size());
  const float fx = static_cast<float>(cam.fx), fy = static_cast<float>(cam.fy);
  const float cx = static_cast<float>(cam.cx), cy = static_cast<float>(cam.cy);
  const float max_u = static_cast<float>(cam.width - 1), max_v = static_cast<float>(cam.height - 1);
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    const Eigen::Vector3f lo = boxes[i].min - o;
    const Eigen::Vector3f hi = boxes[i].max - o;
    // Corners in the camera frame: c = R_cw (lo + s .* (hi - lo)), s in {0,1}^3.
    const Eigen::Vector3f base = R_cw * lo;
    const Eigen::Vector3f ex = R_cw.col(0) * (hi.x() - lo.x());
    const Eigen::Vector3f ey = R_cw.col(1) * (hi.y() - lo.y());
    const Eigen::Vector3f ez = R_cw.col(2) * (hi.z() - lo.z());
    std::array<Eigen::Vector3f, 8> c;
    for (int k = 0; k < 8; ++k) {
      c[static_cast<std::size_t>(k)] = base + ((k & 1) ? ex : Eigen::Vector3f::Zero()) +
                                       ((k & 2) ? ey : Eigen::Vector3f::Zero()) +
                                       ((k & 4) ? ez : Eigen::Vector3f::Zero());
    }
    float u_min = std::numeric_limits<float>::infinity(), u_max = -u_min;
    float v_min = u_min, v_max = -u_min;
    bool any = false;
    auto add_point = [&](const Eigen::Vector3f& p) {
      const float u = fx * p.x() / p.z() + cx;
      const float v = fy * p.y() / p.z() + cy;
      u_min = std::min(u_min, u);
      u_max = std::max(u_max, u);
      v_min = std::min(v_min, v);
      v_max = std::max(v_max, v);
      any = true;
    };
    // The clipped box's vertices: corners in front of the near plane plus the intersections of
    // its edges (corner pairs differing in one bit) with the plane.
    for (int k = 0; k < 8; ++k) {
      const Eigen::Vector3f& a = c[static_cast<std::size_t>(k)];
      if (a.z() > kNearPlane) add_point(a);
      for (const int bit : {1, 2, 4}) {
        if (k & bit) continue;
        const Eigen::Vector3f& b = c[static_cast<std::size_t>(k | bit)];
        if ((a.z() - kNearPlane) * (b.z() - kNearPlane) < 0) {
          add_point(a + (b - a) * ((kNearPlane - a.z()) / (b.z() - a.z())));
        }
      }
    }
    if (!any || u_max < -1.0f || v_max < -1.0f || u_min > max_u + 1.0f || v_min > max_v + 1.0f) {
      continue;
    }
    // Pixels whose centres may see the box, with one pixel of margin for rounding.
    const int px0 = static_cast<int>(std::floor(std::max(u_min, 0.0f))) - 1;
    const int px1 = static_cast<int>(std::ceil(std::min(u_max, max_u))) + 1;
    const int py0 = static_cast<int>(std::floor(std::max(v_min, 0.0f))) - 1;
    const int py1 = static_cast<int>(std::ceil(std::min(v_max, max_v))) + 1;
    const float d_near = lo.cwiseMax(-hi).cwiseMax(0.0f).norm();
    candidates.push_back({d_near, static_cast<int>(i), std::max(px0, 0) / kTile,
                          std::max(py0, 0) / kTile, std::min(px1, cam.width - 1) / kTile,
                          std::min(py1, cam.height - 1) / kTile});
  }
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
    return a.d_near != b.d_near ? a.d_near < b.d_near : a.box < b.box;
  });
  // Two passes: count per tile, then fill in front-to-back order (CSR).
  const int tile_count = view.tiles_x * view.tiles_y;
  view.tile_begin.assign(static_cast<std::size_t>(tile_count) + 1, 0);
  for (const Candidate& cand : candidates) {
    for (int ty = cand.ty0; ty <= cand.ty1; ++ty) {
      for (int tx = cand.tx0; tx <= cand.tx1; ++tx)
        ++view.tile_begin[static_cast<std::size_t>(ty * view.tiles_x + tx) + 1];
    }
  }
  std::partial_sum(view.tile_begin.begin(), view.tile_begin.end(), view.tile_begin.begin());
  view.entries.resize(static_cast<std::size_t>(view.tile_begin.back()));
  std::vector<int> fill(view.tile_begin.begin(), view.tile_begin.end() - 1);
  view.shaders.resize(candidates.size() * 6);
  for (std::size_t c = 0; c < candidates.size(); ++c) {
    const Candidate& cand = candidates[c];
    const Box& b = boxes[static_cast<std::size_t>(cand.box)];
    TileEntry e;
    for (int a = 0; a < 3; ++a) {
      e.lo[a] = b.min[a] - o[a];
      e.hi[a] = b.max[a] - o[a];
    }
    e.d_near = cand.d_near;
    e.box = cand.box;
    e.shaders = static_cast<int>(6 * c);
    for (int face = 0; face < 6; ++face) {
      view.shaders[6 * c + static_cast<std::size_t>(face)] = world_.face_shader(cand.box, face, o);
    }
    for (int ty = cand.ty0; ty <= cand.ty1; ++ty) {
      for (int tx = cand.tx0; tx <= cand.tx1; ++tx) {
        view.entries[static_cast<std::size_t>(
            fill[static_cast<std::size_t>(ty * view.tiles_x + tx)]++)] = e;
      }
    }
  }
}

namespace {

// Four rays at once (four neighbouring pixels of a row) with GCC/Clang vector extensions: the
// slab test of one box against four rays is a handful of vector instructions.
constexpr int kLanes = 4;

inline Float4 splat(float v) { return Float4{v, v, v, v}; }
inline Float4 vmin(Float4 a, Float4 b) { return a < b ? a : b; }
inline Float4 vmax(Float4 a, Float4 b) { return a > b ? a : b; }
inline float hmax(Float4 a) { return std::max(std::max(a[0], a[1]), std::max(a[2], a[3])); }

/// safe_inverse() of four directions' component.
inline Float4 safe_inverse4(Float4 d) {
  const Float4 tiny = splat(1e-12f);
  const Int4 small = (d < tiny) & (d > -tiny);
  const Float4 signed_tiny = d >= splat(0.0f) ? tiny : -tiny;
  return splat(1.0f) / (small ? signed_tiny : d);
}

/// fast_log2() of four values, bit for bit.
inline Float4 fast_log2_4(Float4 x) {
  const Int4 bits = std::bit_cast<Int4>(x);
  const Float4 exponent = __builtin_convertvector((bits >> 23) - 127, Float4);  // x > 0
  const Float4 m = std::bit_cast<Float4>((bits & 0x007FFFFF) | 0x3F800000);     // in [1, 2)
  return exponent + ((-0.34484843f * m + 2.02466578f) * m - 1.67487759f);
}

}  // namespace

std::int64_t Renderer::render_tile_row(const ViewState& view, int tile_row, cv::Mat& out,
                                       cv::Mat* depth) const {
  const int width = view.camera.width;
  const int y_begin = tile_row * kTile;
  const int y_end = std::min(y_begin + kTile, view.camera.height);
  const Eigen::Matrix3f& R = view.R_world_camera;
  const float inf = std::numeric_limits<float>::infinity();
  std::int64_t tests = 0;
  for (int tx = 0; tx < view.tiles_x; ++tx) {
    const std::size_t tile = static_cast<std::size_t>(tile_row * view.tiles_x + tx);
    const TileEntry* begin = view.entries.data() + view.tile_begin[tile];
    const TileEntry* end = view.entries.data() + view.tile_begin[tile + 1];
    const int x_begin = tx * kTile;
    const int x_end = std::min(x_begin + kTile, width);
    for (int y = y_begin; y < y_end; ++y) {
      float* row = out.ptr<float>(y);
      float* depth_row = depth != nullptr ? depth->ptr<float>(y) : nullptr;
      for (int x0 = x_begin; x0 < x_end; x0 += kLanes) {
        const int lanes = std::min(kLanes, x_end - x0);
        // World directions d = R d_cam of the four rays (lanes past the tile repeat the last).
        Float4 cx, cy, cz;
        for (int k = 0; k < kLanes; ++k) {
          const float* dc =
              &view.dirs[(static_cast<std::size_t>(y) * width + x0 + std::min(k, lanes - 1)) * 4];
          cx[k] = dc[0];
          cy[k] = dc[1];
          cz[k] = dc[2];
        }
        const Float4 dx = R(0, 0) * cx + R(0, 1) * cy + R(0, 2) * cz;
        const Float4 dy = R(1, 0) * cx + R(1, 1) * cy + R(1, 2) * cz;
        const Float4 dz = R(2, 0) * cx + R(2, 1) * cy + R(2, 2) * cz;
        const Float4 ix = safe_inverse4(dx), iy = safe_inverse4(dy), iz = safe_inverse4(dz);
        // Nearest entry of each ray (front-to-back list, stop once no ray can do better).
        Float4 t_best = splat(inf);
        Int4 best = {-1, -1, -1, -1};
        for (const TileEntry* e = begin; e != end; ++e) {
          if (e->d_near >= hmax(t_best)) break;
          tests += lanes;
          const Float4 tx0 = e->lo[0] * ix, tx1 = e->hi[0] * ix;
          const Float4 ty0 = e->lo[1] * iy, ty1 = e->hi[1] * iy;
          const Float4 tz0 = e->lo[2] * iz, tz1 = e->hi[2] * iz;
          const Float4 t_enter = vmax(vmax(vmin(tx0, tx1), vmin(ty0, ty1)), vmin(tz0, tz1));
          const Float4 t_exit = vmin(vmin(vmax(tx0, tx1), vmax(ty0, ty1)), vmax(tz0, tz1));
          const Int4 closer = (t_enter <= t_exit) & (t_enter > splat(0.0f)) & (t_enter < t_best);
          t_best = closer ? t_enter : t_best;
          const auto index = static_cast<std::int32_t>(e - begin);
          best = closer ? Int4{index, index, index, index} : best;
        }
        if (depth_row != nullptr) {
          for (int k = 0; k < lanes; ++k) depth_row[x0 + k] = t_best[k];
        }
        const float* angles = &view.dirs[(static_cast<std::size_t>(y) * width + x0) * 4 + 3];
        // Footprint of the pixel on the surface: distance x angular size, stretched by the
        // incidence (geometric mean of the two axes of the footprint ellipse):
        // log2(t * angle / sqrt(cos)) = log2(t^2 * angle^2 / cos) / 2.
        if (lanes == kLanes && best[0] >= 0 && all_lanes(best == best[0])) {
          // All four rays hit one box: the entry face of each (entry_face() in vector form).
          const TileEntry* hit = begin + best[0];
          const Float4 near_x = vmin(hit->lo[0] * ix, hit->hi[0] * ix);
          const Float4 near_y = vmin(hit->lo[1] * iy, hit->hi[1] * iy);
          const Float4 near_z = vmin(hit->lo[2] * iz, hit->hi[2] * iz);
          const Int4 y_beats_x = near_y > near_x;
          const Float4 near_xy = y_beats_x ? near_y : near_x;
          const Int4 z_wins = near_z > near_xy;
          const Int4 axis = z_wins ? Int4{} + 2 : (y_beats_x ? Int4{} + 1 : Int4{});
          if (all_lanes(axis == axis[0])) {
            const Float4 d_axis = axis[0] == 0 ? dx : (axis[0] == 1 ? dy : dz);
            const Float4 inv_axis = axis[0] == 0 ? ix : (axis[0] == 1 ? iy : iz);
            const Int4 positive = inv_axis > 0.0f;
            if (all_lanes(positive == positive[0])) {
              // One face for all four: shade them together (same arithmetic as below).
              const int face = 2 * axis[0] + (positive[0] ? 0 : 1);
              const FaceShader& shader =
                  view.shaders[static_cast<std::size_t>(hit->shaders + face)];
              const Float4 r[3] = {t_best * dx, t_best * dy, t_best * dz};
              const Float4 angle = {angles[0], angles[4], angles[8], angles[12]};
              const Float4 abs_d = d_axis < 0.0f ? -d_axis : d_axis;
              const Float4 cos_incidence = vmax(abs_d, splat(0.05f));
              const Float4 extent = t_best * angle;
              const Float4 log2_footprint =
                  0.5f * fast_log2_4(vmax(extent * extent / cos_incidence, splat(1e-30f)));
              const Float4 radiance = shader.shade4(r, log2_footprint);
              for (int k = 0; k < kLanes; ++k) row[x0 + k] = radiance[k];
              continue;
            }
          }
        }
        for (int k = 0; k < lanes; ++k) {
          const int x = x0 + k;
          const Eigen::Vector3f d(dx[k], dy[k], dz[k]);
          const float t = t_best[k];
          if (best[k] < 0) {
            row[x] = world_.sky_radiance(d);
            continue;
          }
          const TileEntry* hit = begin + best[k];
          const Eigen::Vector3f inv(ix[k], iy[k], iz[k]);
          const int face = entry_face(Eigen::Map<const Eigen::Vector3f>(hit->lo),
                                      Eigen::Map<const Eigen::Vector3f>(hit->hi), inv);
          const float r[3] = {t * dx[k], t * dy[k], t * dz[k]};  // hit point - camera centre
          const float cos_incidence = std::max(std::abs(d[face >> 1]), 0.05f);
          const float extent = t * angles[4 * k];
          const float log2_footprint =
              0.5f * fast_log2(std::max(extent * extent / cos_incidence, 1e-30f));
          row[x] =
              view.shaders[static_cast<std::size_t>(hit->shaders + face)].shade(r, log2_footprint);
        }
      }
    }
  }
  return tests;
}

void Renderer::render(const std::vector<RenderView>& views, std::vector<cv::Mat>& out,
                      std::vector<cv::Mat>* depth) {
  views_.resize(views.size());
  out.resize(views.size());
  if (depth != nullptr) depth->resize(views.size());
  for (std::size_t i = 0; i < views.size(); ++i) {
    prepare_directions(views_[i], views[i].camera);
    out[i].create(views[i].camera.height, views[i].camera.width, CV_32FC1);
    if (depth != nullptr)
      (*depth)[i].create(views[i].camera.height, views[i].camera.width, CV_32FC1);
  }
  common::parallel_for(static_cast<int>(views.size()), threads_, [&](int i) {
    bin_boxes(views_[static_cast<std::size_t>(i)], views[static_cast<std::size_t>(i)]);
  });
  // Work items: (view, tile row), rows of all views interleaved.
  std::vector<std::pair<int, int>> items;
  for (std::size_t i = 0; i < views.size(); ++i) {
    for (int r = 0; r < views_[i].tiles_y; ++r) items.emplace_back(static_cast<int>(i), r);
  }
  std::vector<std::int64_t> tests(items.size(), 0);
  common::parallel_for(static_cast<int>(items.size()), threads_, [&](int k) {
    const auto [v, r] = items[static_cast<std::size_t>(k)];
    const auto vi = static_cast<std::size_t>(v);
    tests[static_cast<std::size_t>(k)] =
        render_tile_row(views_[vi], r, out[vi], depth != nullptr ? &(*depth)[vi] : nullptr);
  });
  stats_ = RenderStats{};
  stats_.box_tests = std::accumulate(tests.begin(), tests.end(), std::int64_t{0});
  for (std::size_t i = 0; i < views.size(); ++i) {
    stats_.rays += static_cast<std::int64_t>(views[i].camera.width) * views[i].camera.height;
    stats_.tile_entries += static_cast<std::int64_t>(views_[i].entries.size());
  }
}

}  // namespace edx::synthetic
