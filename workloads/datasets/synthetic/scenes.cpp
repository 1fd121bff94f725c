#include "workloads/datasets/synthetic/scenes.hpp"

#include <algorithm>
#include <array>
#include <map>
#include <utility>

#include "workloads/datasets/synthetic/random.hpp"
#include "workloads/datasets/synthetic/texture_gen.hpp"

namespace edx::synthetic {

void LaneGraph::add_edge(int a, int b) {
  neighbours[static_cast<std::size_t>(a)].push_back(b);
  neighbours[static_cast<std::size_t>(b)].push_back(a);
}

namespace {

using V3 = Eigen::Vector3f;
using FaceMaterials = std::array<std::uint16_t, 6>;

/// Same material on the four sides, its own on top and bottom.
FaceMaterials faces(std::uint16_t side, std::uint16_t top, std::uint16_t bottom) {
  return {side, side, side, side, bottom, top};
}
FaceMaterials faces(std::uint16_t all) { return faces(all, all, all); }

/// Adds textures, materials and boxes to a world; every random choice comes from one layout
/// stream, every texture from its own stream (kind, variant).
class Builder {
 public:
  Builder(World& world, std::uint64_t seed, std::string_view layout_tag)
      : world_(world), seed_(seed), rng_(derive_seed(seed, layout_tag)) {}

  Rng& rng() { return rng_; }
  double uni(double lo, double hi) { return uniform(rng_, lo, hi); }
  int pick(int count) { return uniform_int(rng_, 0, count - 1); }
  bool chance(double p) { return uniform(rng_, 0, 1) < p; }

  int texture(TextureKind kind, int variant, int size = 512) {
    const auto key = std::make_pair(static_cast<int>(kind), variant);
    if (const auto it = textures_.find(key); it != textures_.end()) return it->second;
    const std::uint64_t tex_seed =
        derive_seed(seed_, to_string(kind), static_cast<unsigned>(variant));
    const int id = world_.add_texture(Texture(make_texture_image(kind, tex_seed, size)));
    textures_.emplace(key, id);
    return id;
  }

  std::uint16_t material(TextureKind kind, int variant, float tile_u, float tile_v,
                         float gain = 1.0f, float offset = 0.0f, int size = 512) {
    Material m;
    m.texture = texture(kind, variant, size);
    m.tile_u_m = tile_u;
    m.tile_v_m = tile_v;
    m.gain = gain;
    m.offset = offset;
    return static_cast<std::uint16_t>(world_.add_material(m));
  }

  /// Box whose textures repeat from a random origin (so repeats do not line up between boxes).
  void tiled(const V3& lo, const V3& hi, const FaceMaterials& m) {
    Box b;
    b.min = lo;
    b.max = hi;
    b.face_material = m;
    b.uv_origin = V3(static_cast<float>(uni(0, 64)), static_cast<float>(uni(0, 64)),
                     static_cast<float>(uni(0, 64)));
    world_.add_box(b);
  }

  /// Box whose textures start at its top-left corner (one tile covers the face when the
  /// material's tile equals the face size).
  void fitted(const V3& lo, const V3& hi, const FaceMaterials& m) {
    Box b;
    b.min = lo;
    b.max = hi;
    b.face_material = m;
    b.uv_origin = V3(lo.x(), lo.y(), hi.z());
    world_.add_box(b);
  }

  /// Box with an explicit texture origin.
  void with_origin(const V3& lo, const V3& hi, const FaceMaterials& m, const V3& origin) {
    Box b;
    b.min = lo;
    b.max = hi;
    b.face_material = m;
    b.uv_origin = origin;
    world_.add_box(b);
  }

 private:
  World& world_;
  std::uint64_t seed_;
  Rng rng_;
  std::map<std::pair<int, int>, int> textures_;
};

V3 v3(double x, double y, double z) {
  return {static_cast<float>(x), static_cast<float>(y), static_cast<float>(z)};
}

/// Box from centre-free corner coordinates with the x/y extents possibly swapped: along_x says
/// whether the "length" axis of a street object runs along x (else along y).
std::pair<V3, V3> oriented(bool along_x, double a0, double a1, double c0, double c1, double z0,
                           double z1) {
  if (along_x) return {v3(a0, c0, z0), v3(a1, c1, z1)};
  return {v3(c0, a0, z0), v3(c1, a1, z1)};
}

// ------------------------------------------------------------------------------------------
// Warehouse
// ------------------------------------------------------------------------------------------

struct WarehouseMaterials {
  std::uint16_t floor, ceiling, bricks, metal, upright, beam0, beam1, wood, tape, pillar;
  std::array<std::uint16_t, 4> cardboard;
  std::array<std::uint16_t, 2> clutter;
};

/// A pallet with a load of cartons on it, occupying [x0, x0 + w] x [y0, y0 + d] from height z.
void pallet_load(Builder& b, const WarehouseMaterials& m, double x0, double y0, double w, double d,
                 double z, double max_height) {
  const double pallet_h = 0.14;
  b.tiled(v3(x0, y0, z), v3(x0 + w, y0 + d, z + pallet_h), faces(m.wood));
  const double top = z + pallet_h;
  const double room = max_height - pallet_h;
  if (room < 0.25) return;
  if (b.chance(0.4)) {
    // One wrapped block of cartons.
    const double h = b.uni(0.35, room);
    const std::uint16_t c = m.cardboard[static_cast<std::size_t>(b.pick(4))];
    b.fitted(v3(x0 + 0.03, y0 + 0.03, top), v3(x0 + w - 0.03, y0 + d - 0.03, top + h), faces(c));
    return;
  }
  // A 2 x 2 grid of cartons of varying heights, some missing.
  for (int i = 0; i < 2; ++i) {
    for (int j = 0; j < 2; ++j) {
      if (b.chance(0.2)) continue;
      const double cw = w / 2 - b.uni(0.03, 0.12);
      const double cd = d / 2 - b.uni(0.03, 0.12);
      const double h = b.uni(0.25, std::min(room, 0.9));
      const double cx = x0 + i * w / 2 + 0.02;
      const double cy = y0 + j * d / 2 + 0.02;
      const std::uint16_t c = m.cardboard[static_cast<std::size_t>(b.pick(4))];
      b.fitted(v3(cx, cy, top), v3(cx + cw, cy + cd, top + h), faces(c));
    }
  }
}

/// Posters on the inner face of a wall. `along_x`: the wall runs along x at coordinate `at`,
/// `inward` is +1 or -1 (direction of the hall interior across the wall).
void wall_posters(Builder& b, bool along_x, double at, double inward, double length, int count) {
  for (int i = 0; i < count; ++i) {
    const double w = b.uni(0.6, 1.5);
    const double h = b.uni(0.7, 1.6);
    const double a0 = b.uni(1.0, length - w - 1.0);
    const double z0 = b.uni(0.9, 2.2);
    const double c0 = inward > 0 ? at : at - 0.02;
    const double c1 = inward > 0 ? at + 0.02 : at;
    const std::uint16_t m =
        b.material(TextureKind::kPoster, b.pick(6), static_cast<float>(w), static_cast<float>(h));
    const auto [lo, hi] = oriented(along_x, a0, a0 + w, c0, c1, z0, z0 + h);
    b.fitted(lo, hi, faces(m));
  }
}

}  // namespace

Scene build_warehouse(std::uint64_t seed) {
  Scene scene;
  scene.outdoor = false;
  World& world = scene.world;
  Builder b(world, seed, "warehouse");
  constexpr double kLength = 44.0, kWidth = 26.0, kHeight = 9.0;

  WarehouseMaterials m{};
  m.floor = b.material(TextureKind::kConcrete, 0, 4.0f, 4.0f);
  m.ceiling = b.material(TextureKind::kCeiling, 0, 4.8f, 4.8f);
  m.bricks = b.material(TextureKind::kBricks, 0, 2.0f, 2.0f);
  m.metal = b.material(TextureKind::kMetalPanels, 0, 4.0f, 4.0f);
  m.upright = b.material(TextureKind::kShelfUpright, 0, 0.2f, 1.0f);
  m.beam0 = b.material(TextureKind::kShelfBeam, 0, 1.4f, 0.14f);
  m.beam1 = b.material(TextureKind::kShelfBeam, 1, 1.4f, 0.14f);
  m.wood = b.material(TextureKind::kWood, 0, 1.2f, 1.2f);
  m.tape = b.material(TextureKind::kPaint, 0, 1.0f, 1.0f, 0.85f);
  m.pillar = b.material(TextureKind::kClutter, 0, 1.6f, 1.6f);
  for (int i = 0; i < 4; ++i) {
    m.cardboard[static_cast<std::size_t>(i)] = b.material(TextureKind::kCardboard, i, 1.0f, 1.0f);
  }
  for (int i = 0; i < 2; ++i) {
    m.clutter[static_cast<std::size_t>(i)] = b.material(TextureKind::kClutter, i + 1, 1.2f, 1.2f);
  }

  // Shell: floor, ceiling, walls (bricks to 3 m, metal cladding above).
  b.tiled(v3(-1, -1, -0.5), v3(kLength + 1, kWidth + 1, 0), faces(m.floor));
  b.tiled(v3(-1, -1, kHeight), v3(kLength + 1, kWidth + 1, kHeight + 0.5), faces(m.ceiling));
  const std::array<std::pair<V3, V3>, 4> walls = {
      std::pair{v3(-0.5, -1, 0), v3(0, kWidth + 1, kHeight)},
      std::pair{v3(kLength, -1, 0), v3(kLength + 0.5, kWidth + 1, kHeight)},
      std::pair{v3(-1, -0.5, 0), v3(kLength + 1, 0, kHeight)},
      std::pair{v3(-1, kWidth, 0), v3(kLength + 1, kWidth + 0.5, kHeight)}};
  for (const auto& [lo, hi] : walls) {
    b.tiled(lo, V3(hi.x(), hi.y(), 3.0f), faces(m.bricks));
    b.tiled(V3(lo.x(), lo.y(), 3.0f), hi, faces(m.metal));
  }
  wall_posters(b, true, 0.0, +1, kLength, 9);
  wall_posters(b, true, kWidth, -1, kLength, 9);
  wall_posters(b, false, 0.0, +1, kWidth, 5);
  wall_posters(b, false, kLength, -1, kWidth, 5);
  // Pillars along the long walls.
  for (double x = 4.0; x < kLength - 1; x += 8.0) {
    b.tiled(v3(x - 0.25, 0, 0), v3(x + 0.25, 0.35, kHeight), faces(m.pillar));
    b.tiled(v3(x - 0.25, kWidth - 0.35, 0), v3(x + 0.25, kWidth, kHeight), faces(m.pillar));
  }

  // Racks: five rows along x, 10 bays of 2.8 m, 4 levels.
  constexpr double kRackX0 = 8.0, kBay = 2.8, kDepth = 1.1;
  constexpr int kBays = 10;
  const std::array<double, 4> levels = {0.0, 1.6, 3.1, 4.6};
  const std::array<double, 5> row_y = {4.4, 8.7, 13.0, 17.3, 21.6};
  for (const double yc : row_y) {
    const double yf = yc - kDepth / 2;  // front face (towards -y)
    const double yb = yc + kDepth / 2;
    for (int k = 0; k <= kBays; ++k) {
      const double x = kRackX0 + k * kBay;
      b.with_origin(v3(x - 0.05, yf, 0), v3(x + 0.05, yf + 0.09, 5.6), faces(m.upright),
                    v3(x - 0.05, yf, 5.6));
      b.with_origin(v3(x - 0.05, yb - 0.09, 0), v3(x + 0.05, yb, 5.6), faces(m.upright),
                    v3(x - 0.05, yb - 0.09, 5.6));
    }
    for (int k = 0; k < kBays; ++k) {
      const double x0 = kRackX0 + k * kBay + 0.05;
      const double x1 = x0 + kBay - 0.1;
      for (std::size_t l = 0; l < levels.size(); ++l) {
        const double z = levels[l];
        if (l > 0) {
          const std::uint16_t beam = b.chance(0.5) ? m.beam0 : m.beam1;
          b.with_origin(v3(x0, yf, z - 0.13), v3(x1, yf + 0.06, z),
                        faces(beam, m.upright, m.upright), v3(x0, yf, z));
          b.with_origin(v3(x0, yb - 0.06, z - 0.13), v3(x1, yb, z),
                        faces(beam, m.upright, m.upright), v3(x0, yb - 0.06, z));
          b.tiled(v3(x0, yf + 0.06, z - 0.03), v3(x1, yb - 0.06, z), faces(m.wood));
        }
        const double max_h = l + 1 < levels.size() ? levels[l + 1] - z - 0.25 : 0.9;
        for (int slot = 0; slot < 2; ++slot) {
          if (b.chance(0.22)) continue;  // empty slot: look through to the next aisle
          const double px = x0 + 0.12 + slot * 1.36;
          pallet_load(b, m, px, yf + 0.05, 1.2, kDepth - 0.1, z, max_h);
        }
      }
    }
    // Floor tape along both sides of the row.
    for (const double y : {yf - 0.25, yb + 0.17}) {
      b.tiled(v3(kRackX0 - 0.5, y, 0), v3(kRackX0 + kBays * kBay + 0.5, y + 0.08, 0.004),
              faces(m.tape));
    }
  }

  // Storage against the end walls (cross aisles) and the side walls.
  for (const double x0 : {0.35, kLength - 1.6}) {
    for (double y = 1.0; y < kWidth - 2.0; y += b.uni(2.2, 3.2)) {
      if (b.chance(0.3)) continue;
      const double stack = b.uni(0.6, 2.2);
      pallet_load(b, m, x0, y, 1.2, 1.0, 0.0, stack);
    }
  }
  for (const double y0 : {0.4, kWidth - 1.0}) {
    for (double x = 9.0; x < kLength - 9.0; x += b.uni(3.0, 6.0)) {
      const double w = b.uni(0.5, 1.0);
      const double h = b.uni(0.6, 1.4);
      b.fitted(v3(x, y0, 0), v3(x + w, y0 + 0.6, h),
               faces(m.clutter[static_cast<std::size_t>(b.pick(2))]));
    }
  }

  world.face_light() = {0.82f, 0.9f, 0.78f, 0.86f, 0.55f, 1.0f};

  // Lanes: six aisles along x (the outer two beside the walls) joined by two cross aisles.
  const std::array<double, 6> lane_y = {2.4, 6.55, 10.85, 15.15, 19.45, 23.6};
  const std::array<double, 2> lane_x = {4.2, 39.8};
  LaneGraph& g = scene.lanes;
  for (const double x : lane_x) {
    for (const double y : lane_y) g.nodes.emplace_back(x, y);
  }
  g.neighbours.resize(g.nodes.size());
  const int n = static_cast<int>(lane_y.size());
  for (int i = 0; i < n; ++i) {
    g.add_edge(i, n + i);
    if (i + 1 < n) {
      g.add_edge(i, i + 1);
      g.add_edge(n + i, n + i + 1);
    }
  }

  MotionLimits& limits = scene.motion;
  limits.style = MotionStyle::kDrone;
  limits.lane_offset_m = 0.0;
  limits.lateral_wander_m = 0.45;
  limits.min_height_m = 0.9;
  limits.max_height_m = 2.5;
  limits.cruise_speed_min = 1.2;
  limits.cruise_speed_max = 2.0;
  limits.turn_speed = 1.0;
  limits.turn_radius_m = 1.5;
  limits.max_accel = 0.6;
  limits.clearance_m = 0.35;
  return scene;
}

// ------------------------------------------------------------------------------------------
// Street grid
// ------------------------------------------------------------------------------------------

namespace {

struct StreetMaterials {
  std::uint16_t asphalt, pavers, curb, roof, paint, bark, foliage, pole;
  std::array<std::uint16_t, 6> facades;
  std::array<std::uint16_t, 2> crates;
};

constexpr double kBlockX = 60.0, kBlockY = 44.0, kCorridor = 18.0;
constexpr int kBlocks = 4;  // per axis; roads run between blocks
constexpr double kSidewalk = 3.0, kCurbH = 0.12;

double block_start_x(int k) { return k * (kBlockX + kCorridor); }
double block_start_y(int k) { return k * (kBlockY + kCorridor); }
double road_x(int i) { return block_start_x(i) + kBlockX + kCorridor / 2; }
double road_y(int j) { return block_start_y(j) + kBlockY + kCorridor / 2; }

/// A parked car with its length along x (along_x) or y, occupying [a0, a0 + len] along the road
/// and centred at c across it.
void parked_car(Builder& b, const StreetMaterials& m, bool along_x, double a0, double len,
                double c) {
  const int side_tex = b.pick(6);
  const int end_tex = b.pick(3);
  const int glass_tex = b.pick(2);
  const float flen = static_cast<float>(len);
  const std::uint16_t side = b.material(TextureKind::kCarSide, side_tex, flen, 0.82f, 1, 0, 256);
  const std::uint16_t end = b.material(TextureKind::kCarEnd, end_tex, 1.8f, 0.82f, 1, 0, 256);
  const float cabin_len = static_cast<float>(0.55 * len);
  const std::uint16_t glass_side =
      b.material(TextureKind::kCarGlass, glass_tex, cabin_len, 0.45f, 1, 0, 256);
  const std::uint16_t glass_end =
      b.material(TextureKind::kCarGlass, glass_tex, 1.6f, 0.45f, 1, 0, 256);
  (void)m;
  // Faces: x-, x+, y-, y+, z-, z+. The long sides face across the road.
  auto body_faces = along_x ? FaceMaterials{end, end, side, side, end, side}
                            : FaceMaterials{side, side, end, end, end, side};
  auto cabin_faces = along_x
                         ? FaceMaterials{glass_end, glass_end, glass_side, glass_side, side, side}
                         : FaceMaterials{glass_side, glass_side, glass_end, glass_end, side, side};
  const auto [blo, bhi] = oriented(along_x, a0, a0 + len, c - 0.9, c + 0.9, 0.18, 1.0);
  b.fitted(blo, bhi, body_faces);
  const double ca0 = a0 + 0.22 * len;
  const auto [clo, chi] = oriented(along_x, ca0, ca0 + 0.55 * len, c - 0.8, c + 0.8, 1.0, 1.45);
  b.fitted(clo, chi, cabin_faces);
}

/// Street furniture and shop fronts along one side of a block. The side runs along x (along_x)
/// or y from a0 to a1; the facade is at coordinate `facade`, the street lies towards `outward`.
void block_side(Builder& b, const StreetMaterials& m, bool along_x, double a0, double a1,
                double facade, double outward) {
  // Buildings: segments of 8..20 m, depth 10..14 m, height 7..24 m.
  double a = a0;
  while (a < a1 - 1e-6) {
    double w = b.uni(8, 20);
    if (a1 - (a + w) < 6) w = a1 - a;
    const double depth = b.uni(10, 14);
    const double h = b.uni(7, 24);
    const double c_out = facade;
    const double c_in = facade - outward * depth;
    const auto [lo, hi] =
        oriented(along_x, a, a + w, std::min(c_out, c_in), std::max(c_out, c_in), kCurbH, h);
    const std::uint16_t facade_mat = m.facades[static_cast<std::size_t>(b.pick(6))];
    b.with_origin(lo, hi, faces(facade_mat, m.roof, m.roof),
                  V3(lo.x() + static_cast<float>(b.uni(0, 9)),
                     lo.y() + static_cast<float>(b.uni(0, 9)), static_cast<float>(kCurbH + 6.0)));
    if (b.chance(0.45) && w > 4) {
      // Shop front: a thin box in front of the ground floor, one texture tile across.
      const double sw = w - 1.0;
      const std::uint16_t shop =
          b.material(TextureKind::kShopFront, b.pick(4), static_cast<float>(sw), 3.4f);
      const double s0 = facade, s1 = facade + outward * 0.15;
      const auto [slo, shi] = oriented(along_x, a + 0.5, a + 0.5 + sw, std::min(s0, s1),
                                       std::max(s0, s1), kCurbH, kCurbH + 3.4);
      b.fitted(slo, shi, faces(shop, m.roof, m.roof));
    }
    a += w;
  }
  // Furniture on the sidewalk: lamp posts and trees near the curb, crates, bins and poster
  // stands near the facade.
  for (double s = a0 + b.uni(3, 8); s < a1 - 3; s += b.uni(7, 16)) {
    const double curb_side = facade + outward * (kSidewalk - 0.6);
    const double wall_side = facade + outward * 0.9;
    switch (b.pick(5)) {
      case 0: {  // lamp post
        const auto [lo, hi] =
            oriented(along_x, s - 0.07, s + 0.07, curb_side - 0.07, curb_side + 0.07, kCurbH, 5.5);
        b.tiled(lo, hi, faces(m.pole));
        const double head0 = curb_side, head1 = curb_side + outward * 0.9;
        const auto [hlo, hhi] = oriented(along_x, s - 0.12, s + 0.12, std::min(head0, head1),
                                         std::max(head0, head1), 5.35, 5.55);
        b.tiled(hlo, hhi, faces(m.pole));
        break;
      }
      case 1: {  // tree
        const double c = facade + outward * 2.1;
        const auto [lo, hi] =
            oriented(along_x, s - 0.17, s + 0.17, c - 0.17, c + 0.17, kCurbH, 2.8);
        b.tiled(lo, hi, faces(m.bark));
        const double r = b.uni(0.9, 1.2);
        const auto [clo, chi] = oriented(along_x, s - r, s + r, c - r, c + r, 2.8, 2.8 + 2 * r);
        b.tiled(clo, chi, faces(m.foliage));
        break;
      }
      case 2: {  // poster stand, facing along the sidewalk both ways
        const std::uint16_t poster = b.material(TextureKind::kPoster, b.pick(6), 0.1f, 1.8f);
        const std::uint16_t poster_face = b.material(TextureKind::kPoster, b.pick(6), 1.2f, 1.8f);
        const auto [lo, hi] =
            oriented(along_x, s - 0.05, s + 0.05, wall_side - 0.6, wall_side + 0.6, 0.35, 2.15);
        FaceMaterials f =
            along_x ? FaceMaterials{poster_face, poster_face, poster, poster, m.pole, m.pole}
                    : FaceMaterials{poster, poster, poster_face, poster_face, m.pole, m.pole};
        b.fitted(lo, hi, f);
        break;
      }
      default: {  // a stack of crates or bins against the facade
        const int count = 1 + b.pick(3);
        double z = kCurbH;
        const double w = b.uni(0.6, 1.1);
        for (int i = 0; i < count; ++i) {
          const double h = b.uni(0.4, 0.8);
          const double c0 = facade + outward * 0.1, c1 = facade + outward * (0.1 + b.uni(0.5, 0.9));
          const auto [lo, hi] =
              oriented(along_x, s - w / 2, s + w / 2, std::min(c0, c1), std::max(c0, c1), z, z + h);
          b.fitted(lo, hi, faces(m.crates[static_cast<std::size_t>(b.pick(2))]));
          z += h;
        }
      }
    }
  }
}

/// Road markings and parked cars along one road corridor. The road runs along x (along_x) at
/// cross coordinate `centre`, from 0 to `length`; junctions at `junctions` (coordinates along
/// the road) are kept free of cars and get zebra crossings.
void road(Builder& b, const StreetMaterials& m, bool along_x, double centre, double length,
          const std::array<double, 3>& junctions) {
  const double half = kCorridor / 2 - kSidewalk;  // 6 m: curb to road centre
  auto near_junction = [&](double a, double margin) {
    return std::any_of(junctions.begin(), junctions.end(),
                       [&](double j) { return std::abs(a - j) < kCorridor / 2 + margin; });
  };
  // Centre dashes (3 m every 9 m) and solid lane edge lines between junctions.
  for (double a = 1.0; a < length - 3; a += 9.0) {
    if (near_junction(a, 1.0) || near_junction(a + 3, 1.0)) continue;
    const auto [lo, hi] = oriented(along_x, a, a + 3, centre - 0.07, centre + 0.07, 0, 0.006);
    b.tiled(lo, hi, faces(m.paint));
  }
  std::vector<double> stops = {0.0};
  for (const double j : junctions) {
    stops.push_back(j - kCorridor / 2 - 5.0);
    stops.push_back(j + kCorridor / 2 + 5.0);
  }
  stops.push_back(length);
  for (std::size_t i = 0; i + 1 < stops.size(); i += 2) {
    for (const double side : {-1.0, 1.0}) {
      const double c = centre + side * (half - 2.0);
      const auto [lo, hi] = oriented(along_x, stops[i], stops[i + 1], c - 0.06, c + 0.06, 0, 0.006);
      b.tiled(lo, hi, faces(m.paint));
    }
  }
  // Zebra crossings on every approach to a junction.
  for (const double j : junctions) {
    for (const double dir : {-1.0, 1.0}) {
      const double a0 = j + dir * (kCorridor / 2 + 1.0);
      const double a1 = j + dir * (kCorridor / 2 + 4.0);
      for (double c = centre - half + 0.5; c < centre + half - 0.5; c += 1.0) {
        const auto [lo, hi] =
            oriented(along_x, std::min(a0, a1), std::max(a0, a1), c, c + 0.5, 0, 0.006);
        b.tiled(lo, hi, faces(m.paint));
      }
    }
  }
  // Parked cars in the 2 m parking strips along both curbs.
  for (const double side : {-1.0, 1.0}) {
    const double c = centre + side * (half - 1.0);
    double a = b.uni(0.5, 4.0);
    while (a < length - 5.0) {
      const double len = b.uni(3.9, 4.9);
      if (near_junction(a, 10.0) || near_junction(a + len, 10.0)) {
        a += 2.0;
        continue;
      }
      if (b.chance(0.75)) parked_car(b, m, along_x, a, len, c);
      a += len + b.uni(0.8, 5.0);
    }
  }
}

}  // namespace

Scene build_street(std::uint64_t seed) {
  Scene scene;
  scene.outdoor = true;
  World& world = scene.world;
  Builder b(world, seed, "street");
  const double extent_x = block_start_x(kBlocks - 1) + kBlockX;
  const double extent_y = block_start_y(kBlocks - 1) + kBlockY;

  StreetMaterials m{};
  m.asphalt = b.material(TextureKind::kAsphalt, 0, 6.0f, 6.0f);
  m.pavers = b.material(TextureKind::kPavers, 0, 4.0f, 4.0f);
  m.curb = b.material(TextureKind::kConcrete, 0, 3.0f, 3.0f);
  m.roof = b.material(TextureKind::kConcrete, 1, 6.0f, 6.0f, 0.9f);
  m.paint = b.material(TextureKind::kPaint, 0, 2.0f, 2.0f);
  m.bark = b.material(TextureKind::kBark, 0, 1.0f, 2.0f);
  m.foliage = b.material(TextureKind::kFoliage, 0, 2.0f, 2.0f);
  m.pole = b.material(TextureKind::kBark, 1, 0.5f, 3.0f, 0.8f, 30.0f);
  for (int i = 0; i < 6; ++i) {
    m.facades[static_cast<std::size_t>(i)] = b.material(TextureKind::kFacade, i, 9.0f, 6.0f);
  }
  m.crates[0] = b.material(TextureKind::kCardboard, 0, 1.0f, 1.0f);
  m.crates[1] = b.material(TextureKind::kWood, 0, 1.0f, 1.0f);

  // Ground, and a ring of tall buildings closing the world.
  b.tiled(v3(-40, -40, -0.5), v3(extent_x + 40, extent_y + 40, 0), faces(m.asphalt));
  const std::array<std::pair<V3, V3>, 4> ring = {
      std::pair{v3(-14, -14, 0), v3(0, extent_y + 14, 30)},
      std::pair{v3(extent_x, -14, 0), v3(extent_x + 14, extent_y + 14, 30)},
      std::pair{v3(-14, -14, 0), v3(extent_x + 14, 0, 30)},
      std::pair{v3(-14, extent_y, 0), v3(extent_x + 14, extent_y + 14, 30)}};
  for (const auto& [lo, hi] : ring) {
    b.with_origin(lo, hi, faces(m.facades[static_cast<std::size_t>(b.pick(6))], m.roof, m.roof),
                  V3(0, 0, 6.0f));
  }

  // Blocks: sidewalk slab (curb on its sides) and buildings along the four sides.
  for (int kx = 0; kx < kBlocks; ++kx) {
    for (int ky = 0; ky < kBlocks; ++ky) {
      const double x0 = block_start_x(kx), x1 = x0 + kBlockX;
      const double y0 = block_start_y(ky), y1 = y0 + kBlockY;
      b.tiled(v3(x0 - kSidewalk, y0 - kSidewalk, 0), v3(x1 + kSidewalk, y1 + kSidewalk, kCurbH),
              faces(m.curb, m.pavers, m.curb));
      block_side(b, m, true, x0, x1, y0, -1);
      block_side(b, m, true, x0, x1, y1, +1);
      block_side(b, m, false, y0, y1, x0, -1);
      block_side(b, m, false, y0, y1, x1, +1);
    }
  }

  // Roads: three along x, three along y, each through three junctions.
  const std::array<double, 3> jx = {road_x(0), road_x(1), road_x(2)};
  const std::array<double, 3> jy = {road_y(0), road_y(1), road_y(2)};
  for (const double y : jy) road(b, m, true, y, extent_x, jx);
  for (const double x : jx) road(b, m, false, x, extent_y, jy);

  Sky& sky = world.sky();
  sky.enabled = true;
  sky.cloud_texture = b.texture(TextureKind::kClouds, 0);
  world.face_light() = {0.7f, 0.95f, 0.8f, 0.62f, 0.45f, 1.0f};

  LaneGraph& g = scene.lanes;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j)
      g.nodes.emplace_back(jx[static_cast<std::size_t>(i)], jy[static_cast<std::size_t>(j)]);
  }
  g.neighbours.resize(g.nodes.size());
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      if (i + 1 < 3) g.add_edge(i * 3 + j, (i + 1) * 3 + j);
      if (j + 1 < 3) g.add_edge(i * 3 + j, i * 3 + j + 1);
    }
  }

  MotionLimits& limits = scene.motion;
  limits.style = MotionStyle::kCar;
  limits.lane_offset_m = 2.0;
  limits.lateral_wander_m = 0.0;
  limits.min_height_m = 0.9;
  limits.max_height_m = 0.9;
  limits.cruise_speed_min = 7.0;
  limits.cruise_speed_max = 12.0;
  limits.turn_speed = 5.0;
  limits.turn_radius_m = 6.0;
  limits.max_accel = 2.0;
  limits.clearance_m = 0.6;
  return scene;
}

}  // namespace edx::synthetic
