#pragma once
// The synthetic world: textured axis-aligned boxes under a procedural sky.
//
// Faces are numbered 2*axis + side, side 1 for the face whose outward normal points along
// +axis. Texture coordinates on a face follow the viewer: u runs to the viewer's right and v
// downwards on vertical faces (u along +x, v along +y on horizontal faces), in tiles of the
// material's size, relative to the box's uv_origin. Radiance of a hit:
//   L = light[face] * (gain * T(u, v, lod) + offset),   T the (b)rilinear texture sample,
// with lod = log2(footprint / texel size), footprint the pixel's extent on the surface.
#include <Eigen/Core>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

#include "workloads/datasets/synthetic/texture.hpp"

namespace edx::synthetic {

/// log2(x) for x > 0 to about 0.005: exponent plus a quadratic in the mantissa (for mip levels,
/// where speed matters more than precision).
inline float fast_log2(float x) {
  const std::uint32_t bits = std::bit_cast<std::uint32_t>(x);
  const float exponent = static_cast<float>(static_cast<int>(bits >> 23) - 127);
  const float m = std::bit_cast<float>((bits & 0x007FFFFFu) | 0x3F800000u);  // in [1, 2)
  return exponent + ((-0.34484843f * m + 2.02466578f) * m - 1.67487759f);
}

/// How a texture covers a face.
struct Material {
  int texture = 0;
  float tile_u_m = 1.0f;  ///< metres per texture repeat along u
  float tile_v_m = 1.0f;  ///< metres per texture repeat along v
  float gain = 1.0f;
  float offset = 0.0f;
};

/// An axis-aligned box with one material per face.
struct Box {
  Eigen::Vector3f min = Eigen::Vector3f::Zero();
  Eigen::Vector3f max = Eigen::Vector3f::Zero();
  std::array<std::uint16_t, 6> face_material{};
  Eigen::Vector3f uv_origin = Eigen::Vector3f::Zero();  ///< world point where (u, v) = (0, 0)
};

/// First intersection of a ray with the boxes.
struct Hit {
  float t = std::numeric_limits<float>::infinity();  ///< distance along the unit direction
  int box = -1;
  int face = -1;
};

/// Sky seen by rays that leave the world: a vertical gradient with clouds on a plane above.
struct Sky {
  bool enabled = false;  ///< disabled: black (indoor worlds are closed, so never seen)
  int cloud_texture = -1;
  float cloud_tile_m = 600.0f;  ///< cloud texture repeat on the cloud plane
  float cloud_height_m = 300.0f;
  float horizon = 205.0f;  ///< radiance at the horizon
  float zenith = 150.0f;   ///< radiance straight up (before clouds)
};

/// Slab test of a ray (origin o, inverse direction inv_dir) against [lo, hi]. Returns the entry
/// distance, or +inf when missed or behind the origin. The origin is assumed outside the box.
inline float ray_box_entry(const Eigen::Vector3f& lo_minus_o, const Eigen::Vector3f& hi_minus_o,
                           const Eigen::Vector3f& inv_dir) {
  const float tx0 = lo_minus_o.x() * inv_dir.x(), tx1 = hi_minus_o.x() * inv_dir.x();
  const float ty0 = lo_minus_o.y() * inv_dir.y(), ty1 = hi_minus_o.y() * inv_dir.y();
  const float tz0 = lo_minus_o.z() * inv_dir.z(), tz1 = hi_minus_o.z() * inv_dir.z();
  const float t_enter =
      std::max(std::max(std::min(tx0, tx1), std::min(ty0, ty1)), std::min(tz0, tz1));
  const float t_exit =
      std::min(std::min(std::max(tx0, tx1), std::max(ty0, ty1)), std::max(tz0, tz1));
  return (t_enter <= t_exit && t_enter > 0.0f) ? t_enter : std::numeric_limits<float>::infinity();
}

/// The face through which a ray with direction `dir` entered box [lo, hi] at distance t.
inline int entry_face(const Eigen::Vector3f& lo_minus_o, const Eigen::Vector3f& hi_minus_o,
                      const Eigen::Vector3f& inv_dir) {
  int axis = 0;
  float best = -std::numeric_limits<float>::infinity();
  for (int a = 0; a < 3; ++a) {
    const float t0 = lo_minus_o[a] * inv_dir[a];
    const float t1 = hi_minus_o[a] * inv_dir[a];
    const float t_near = std::min(t0, t1);
    if (t_near > best) {
      best = t_near;
      axis = a;
    }
  }
  // Moving along +axis the ray enters through the min face (outward normal -axis).
  return 2 * axis + (inv_dir[axis] > 0.0f ? 0 : 1);
}

/// Component-wise inverse of a direction; zero components become +-huge instead of inf so that
/// 0 * inv never yields NaN in the slab test.
inline Eigen::Vector3f safe_inverse(const Eigen::Vector3f& d) {
  Eigen::Vector3f inv;
  for (int a = 0; a < 3; ++a) {
    const float c = std::abs(d[a]) < 1e-12f ? std::copysign(1e-12f, d[a]) : d[a];
    inv[a] = 1.0f / c;
  }
  return inv;
}

/// The shading of one face of one box as seen from a viewpoint o: for the surface point
/// p = o + r,
///   u = u_scale r[u_axis] + u_offset,  v = v_scale r[v_axis] + v_offset   (tiles),
///   L = light_gain T(u, v, log2_footprint + lod_offset) + light_offset,
/// i.e. face_uv() and light * (gain T + offset) with the per-face constants folded.
struct FaceShader {
  const Texture* texture = nullptr;
  int u_axis = 0, v_axis = 1;
  float u_scale = 1, v_scale = 1, u_offset = 0, v_offset = 0;
  float lod_offset = 0;
  float light_gain = 1, light_offset = 0;

  /// Radiance at r (3 floats, relative to the viewpoint) seen with a pixel footprint of
  /// 2^log2_footprint metres.
  float shade(const float* r, float log2_footprint) const {
    const float u = u_scale * r[u_axis] + u_offset;
    const float v = v_scale * r[v_axis] + v_offset;
    return light_gain * texture->sample(u, v, log2_footprint + lod_offset) + light_offset;
  }

  /// shade() of four points (r[axis] holds the four values of that axis), bit for bit.
  Float4 shade4(const Float4* r, Float4 log2_footprint) const {
    const Float4 u = u_scale * r[u_axis] + u_offset;
    const Float4 v = v_scale * r[v_axis] + v_offset;
    return light_gain * texture->sample4(u, v, log2_footprint + lod_offset) + light_offset;
  }
};

class World {
 public:
  World() = default;
  World(const World& other);
  World& operator=(const World& other);
  World(World&&) noexcept = default;  // moving the vectors keeps texture addresses valid
  World& operator=(World&&) noexcept = default;

  int add_texture(Texture texture);
  int add_material(const Material& material);
  /// Adds a box; `uv_origin` defaults to box.min (for tiled materials, pass a random origin so
  /// repeated textures do not line up).
  int add_box(const Box& box);

  const std::vector<Box>& boxes() const { return boxes_; }
  const std::vector<Material>& materials() const { return materials_; }
  const std::vector<Texture>& textures() const { return textures_; }
  Sky& sky() { return sky_; }
  const Sky& sky() const { return sky_; }
  /// Relative brightness of each face orientation (a fixed directional light).
  std::array<float, 6>& face_light() { return face_light_; }

  /// First hit of the ray o + t d (d unit length), t in (0, t_max); brute force over all boxes.
  /// For queries and tests; the renderer uses its own per-frame acceleration structure.
  Hit cast(const Eigen::Vector3f& origin, const Eigen::Vector3f& dir,
           float t_max = std::numeric_limits<float>::infinity()) const;

  /// Euclidean distance from p to the nearest box (0 inside a box).
  double distance_to_geometry(const Eigen::Vector3d& p) const;

  /// Texture coordinates (u, v) in tiles of point p on `face` of `box`.
  Eigen::Vector2f face_uv(int box, int face, const Eigen::Vector3f& p) const {
    const Box& b = boxes_[static_cast<std::size_t>(box)];
    return face_uv(b, material_info_[b.face_material[static_cast<std::size_t>(face)]], face, p);
  }

  /// Radiance of point p on `face` of `box`, seen with a pixel footprint of `footprint_m`
  /// metres (selects the mip level: lod = log2(footprint * texels per metre)).
  float shade(int box, int face, const Eigen::Vector3f& p, float footprint_m) const {
    return shade_log_footprint(box, face, p, fast_log2(std::max(footprint_m, 1e-9f)));
  }

  /// As shade(), with log2 of the footprint given.
  float shade_log_footprint(int box, int face, const Eigen::Vector3f& p,
                            float log2_footprint) const {
    return face_shader(box, face, Eigen::Vector3f::Zero()).shade(p.data(), log2_footprint);
  }

  /// The shading of one face of one box folded into a few constants, for points given relative
  /// to a viewpoint `origin` (p = origin + r); see FaceShader.
  FaceShader face_shader(int box, int face, const Eigen::Vector3f& origin) const {
    const Box& b = boxes_[static_cast<std::size_t>(box)];
    const MaterialInfo& info = material_info_[b.face_material[static_cast<std::size_t>(face)]];
    const FaceAxes& a = kFaceAxes[static_cast<std::size_t>(face)];
    const float light = face_light_[static_cast<std::size_t>(face)];
    FaceShader s;
    s.texture = info.texture;
    s.u_axis = a.u_axis;
    s.v_axis = a.v_axis;
    s.u_scale = a.u_sign * info.inv_tile_u;
    s.v_scale = a.v_sign * info.inv_tile_v;
    s.u_offset = s.u_scale * (origin[a.u_axis] - b.uv_origin[a.u_axis]);
    s.v_offset = s.v_scale * (origin[a.v_axis] - b.uv_origin[a.v_axis]);
    s.lod_offset = info.log2_texels_per_m;
    s.light_gain = light * info.gain;
    s.light_offset = light * info.offset;
    return s;
  }

  /// Radiance of the sky in world direction d (unit).
  float sky_radiance(const Eigen::Vector3f& d) const;

 private:
  std::vector<Texture> textures_;
  std::vector<Material> materials_;
  /// Per material, precomputed for shading: texture, inverse tile sizes, log2 texel density.
  struct MaterialInfo {
    const Texture* texture = nullptr;
    float inv_tile_u = 1, inv_tile_v = 1;
    float gain = 1, offset = 0;
    float log2_texels_per_m = 0;  ///< level-0 texels per metre along the finer axis
  };

  /// Per face: the world axes of u and v and their signs. Viewer's right on a vertical face
  /// with outward normal n is (-n) x z: +y on the +x face, -y on the -x face, -x on the +y face,
  /// +x on the -y face; v runs down (-z) on vertical faces, along +y on horizontal ones.
  struct FaceAxes {
    int u_axis, v_axis;
    float u_sign, v_sign;
  };
  static constexpr std::array<FaceAxes, 6> kFaceAxes = {{{1, 2, -1.0f, -1.0f},
                                                         {1, 2, 1.0f, -1.0f},
                                                         {0, 2, 1.0f, -1.0f},
                                                         {0, 2, -1.0f, -1.0f},
                                                         {0, 1, 1.0f, 1.0f},
                                                         {0, 1, 1.0f, 1.0f}}};

  static Eigen::Vector2f face_uv(const Box& b, const MaterialInfo& m, int face,
                                 const Eigen::Vector3f& p) {
    const FaceAxes& a = kFaceAxes[static_cast<std::size_t>(face)];
    return {a.u_sign * (p[a.u_axis] - b.uv_origin[a.u_axis]) * m.inv_tile_u,
            a.v_sign * (p[a.v_axis] - b.uv_origin[a.v_axis]) * m.inv_tile_v};
  }

  void refresh_material_info();

  std::vector<MaterialInfo> material_info_;
  std::vector<Box> boxes_;
  Sky sky_;
  std::array<float, 6> face_light_{0.8f, 0.8f, 0.8f, 0.8f, 0.6f, 1.0f};
};

}  // namespace edx::synthetic
