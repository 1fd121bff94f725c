#include "workloads/datasets/synthetic/world.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace edx::synthetic {

World::World(const World& other)
    : textures_(other.textures_),
      materials_(other.materials_),
      boxes_(other.boxes_),
      sky_(other.sky_),
      face_light_(other.face_light_) {
  refresh_material_info();
}

World& World::operator=(const World& other) {
  if (this != &other) {
    textures_ = other.textures_;
    materials_ = other.materials_;
    boxes_ = other.boxes_;
    sky_ = other.sky_;
    face_light_ = other.face_light_;
    refresh_material_info();
  }
  return *this;
}

int World::add_texture(Texture texture) {
  textures_.push_back(std::move(texture));
  refresh_material_info();
  return static_cast<int>(textures_.size()) - 1;
}

int World::add_material(const Material& material) {
  if (material.texture < 0 || material.texture >= static_cast<int>(textures_.size())) {
    throw std::runtime_error("synthetic world: material refers to texture " +
                             std::to_string(material.texture) + " of " +
                             std::to_string(textures_.size()));
  }
  if (!(material.tile_u_m > 0) || !(material.tile_v_m > 0)) {
    throw std::runtime_error("synthetic world: material tile size must be positive");
  }
  if (materials_.size() >= 0xFFFF) {
    throw std::runtime_error("synthetic world: too many materials (max 65535)");
  }
  materials_.push_back(material);
  refresh_material_info();
  return static_cast<int>(materials_.size()) - 1;
}

void World::refresh_material_info() {
  // Texture addresses change when textures_ grows, so the table is rebuilt after every change.
  material_info_.resize(materials_.size());
  for (std::size_t i = 0; i < materials_.size(); ++i) {
    const Material& m = materials_[i];
    MaterialInfo& info = material_info_[i];
    info.texture = &textures_[static_cast<std::size_t>(m.texture)];
    info.inv_tile_u = 1.0f / m.tile_u_m;
    info.inv_tile_v = 1.0f / m.tile_v_m;
    info.gain = m.gain;
    info.offset = m.offset;
    info.log2_texels_per_m =
        std::log2(static_cast<float>(info.texture->size()) / std::min(m.tile_u_m, m.tile_v_m));
  }
}

int World::add_box(const Box& box) {
  if (!(box.min.array() < box.max.array()).all()) {
    throw std::runtime_error("synthetic world: box with empty extent");
  }
  for (const std::uint16_t m : box.face_material) {
    if (m >= materials_.size()) {
      throw std::runtime_error("synthetic world: box refers to material " + std::to_string(m));
    }
  }
  boxes_.push_back(box);
  return static_cast<int>(boxes_.size()) - 1;
}

Hit World::cast(const Eigen::Vector3f& origin, const Eigen::Vector3f& dir, float t_max) const {
  const Eigen::Vector3f inv = safe_inverse(dir);
  Hit hit;
  hit.t = t_max;
  for (std::size_t i = 0; i < boxes_.size(); ++i) {
    const float t = ray_box_entry(boxes_[i].min - origin, boxes_[i].max - origin, inv);
    if (t < hit.t) {
      hit.t = t;
      hit.box = static_cast<int>(i);
    }
  }
  if (hit.box >= 0) {
    const Box& b = boxes_[static_cast<std::size_t>(hit.box)];
    hit.face = entry_face(b.min - origin, b.max - origin, inv);
  } else {
    hit.t = std::numeric_limits<float>::infinity();
  }
  return hit;
}

double World::distance_to_geometry(const Eigen::Vector3d& p) const {
  double best_sq = std::numeric_limits<double>::infinity();
  for (const Box& b : boxes_) {
    const Eigen::Vector3d lo = b.min.cast<double>() - p;
    const Eigen::Vector3d hi = p - b.max.cast<double>();
    const Eigen::Vector3d outside = lo.cwiseMax(hi).cwiseMax(0.0);
    best_sq = std::min(best_sq, outside.squaredNorm());
  }
  return std::sqrt(best_sq);
}

float World::sky_radiance(const Eigen::Vector3f& d) const {
  if (!sky_.enabled) return 0.0f;
  const float up = std::max(d.z(), 0.0f);
  // Brighter towards the horizon: L = zenith + (horizon - zenith) (1 - up)^3.
  const float k = 1.0f - up;
  float radiance = sky_.zenith + (sky_.horizon - sky_.zenith) * k * k * k;
  if (sky_.cloud_texture >= 0 && d.z() > 0.02f) {
    // Clouds on a horizontal plane at cloud_height_m, fading out towards the horizon.
    const float s = sky_.cloud_height_m / d.z();
    const float u = d.x() * s / sky_.cloud_tile_m;
    const float v = d.y() * s / sky_.cloud_tile_m;
    const Texture& tex = textures_[static_cast<std::size_t>(sky_.cloud_texture)];
    const float lod = std::log2(std::max(s * 2e-3f / (sky_.cloud_tile_m / tex.size()), 1e-6f));
    const float cloud = tex.sample(u, v, lod);
    const float fade = std::min(1.0f, d.z() * 4.0f);
    radiance += fade * (cloud - 170.0f);
  }
  return radiance;
}

}  // namespace edx::synthetic
