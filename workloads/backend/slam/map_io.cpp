// JSON reading and writing of the SLAM map (format in map.hpp).
#include <fmt/format.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <stdexcept>
#include <unordered_map>

#include "common/atomic_file.hpp"
#include "workloads/backend/slam/map.hpp"

namespace edx::backend::slam {
namespace {

using nlohmann::json;

std::string to_hex(const Descriptor& d) {
  std::string s;
  for (std::uint8_t byte : d) s += fmt::format("{:02x}", byte);
  return s;
}

json pose_to_json(const Eigen::Isometry3d& T) {
  const Eigen::Quaterniond q(T.linear());
  const Eigen::Vector3d t = T.translation();
  return json::array({t.x(), t.y(), t.z(), q.w(), q.x(), q.y(), q.z()});
}

/// Reads one file with context for messages: "FILE: path.to.key: expected WHAT".
class Reader {
 public:
  explicit Reader(std::filesystem::path file) : file_(std::move(file)) {}

  [[noreturn]] void fail(const std::string& where, const std::string& expected) const {
    throw std::runtime_error(fmt::format("{}: {}: expected {}", file_.string(), where, expected));
  }
  const json& at(const json& object, const std::string& where, const char* key) const {
    if (!object.is_object() || !object.contains(key)) fail(where + "." + key, "a value (missing)");
    return object.at(key);
  }
  double number(const json& object, const std::string& where, const char* key) const {
    const json& v = at(object, where, key);
    if (!v.is_number()) fail(where + "." + key, "a number");
    return v.get<double>();
  }
  std::int64_t integer(const json& object, const std::string& where, const char* key) const {
    const json& v = at(object, where, key);
    if (!v.is_number_integer()) fail(where + "." + key, "an integer");
    return v.get<std::int64_t>();
  }
  const json& array(const json& object, const std::string& where, const char* key) const {
    const json& v = at(object, where, key);
    if (!v.is_array()) fail(where + "." + key, "an array");
    return v;
  }
  Eigen::VectorXd numbers(const json& v, const std::string& where, std::size_t n) const {
    if (!v.is_array() || v.size() != n) fail(where, fmt::format("an array of {} numbers", n));
    Eigen::VectorXd out(static_cast<Eigen::Index>(n));
    for (std::size_t i = 0; i < n; ++i) {
      if (!v[i].is_number()) fail(where, fmt::format("an array of {} numbers", n));
      out(static_cast<Eigen::Index>(i)) = v[i].get<double>();
    }
    return out;
  }
  Eigen::Isometry3d pose(const json& object, const std::string& where, const char* key) const {
    const Eigen::VectorXd v = numbers(at(object, where, key), where + "." + key, 7);
    Eigen::Quaterniond q(v(3), v(4), v(5), v(6));
    if (std::abs(q.norm() - 1.0) > 1e-6) {
      fail(where + "." + key, "[tx, ty, tz, qw, qx, qy, qz] with a unit quaternion");
    }
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = q.normalized().toRotationMatrix();
    T.translation() = v.head<3>();
    return T;
  }
  Descriptor descriptor(const json& object, const std::string& where) const {
    const json& v = at(object, where, "descriptor");
    const std::string text = v.is_string() ? v.get<std::string>() : std::string();
    if (text.size() != 64 || text.find_first_not_of("0123456789abcdef") != std::string::npos) {
      fail(where + ".descriptor", "a string of 64 lowercase hex digits");
    }
    Descriptor d{};
    for (std::size_t i = 0; i < 32; ++i) {
      d[i] = static_cast<std::uint8_t>(std::stoi(text.substr(2 * i, 2), nullptr, 16));
    }
    return d;
  }

 private:
  std::filesystem::path file_;
};

}  // namespace

void save_map(const Map& map, const std::filesystem::path& path) {
  json j;
  j["format"] = kMapFormatName;
  j["version"] = kMapFormatVersion;
  j["source"] = map.source;
  const BackendCamera& c = map.camera;
  j["camera"] = {{"width", c.width},
                 {"height", c.height},
                 {"fx", c.fx},
                 {"fy", c.fy},
                 {"cx", c.cx},
                 {"cy", c.cy},
                 {"baseline_m", c.baseline_m},
                 {"T_body_left", pose_to_json(c.T_body_left)}};
  json keyframes = json::array();
  for (const MapKeyframe& kf : map.keyframes) {
    json keypoints = json::array();
    for (const MapKeypoint& k : kf.keypoints) {
      keypoints.push_back({{"track_id", k.track_id},
                           {"left", {k.left.x(), k.left.y()}},
                           {"right", k.right ? json{k.right->x(), k.right->y()} : json(nullptr)},
                           {"depth_m", k.depth_m},
                           {"octave", k.octave},
                           {"angle", k.angle_deg},
                           {"descriptor", to_hex(k.descriptor)}});
    }
    keyframes.push_back({{"id", kf.id},
                         {"t_ns", kf.t_ns},
                         {"frame_index", kf.frame_index},
                         {"T_world_body", pose_to_json(kf.T_world_body)},
                         {"keypoints", std::move(keypoints)}});
  }
  j["keyframes"] = std::move(keyframes);
  json landmarks = json::array();
  for (const MapLandmark& l : map.landmarks) {
    json observations = json::array();
    for (const MapObservation& o : l.observations) {
      observations.push_back({o.keyframe_id, o.keypoint_index});
    }
    landmarks.push_back({{"id", l.id},
                         {"track_id", l.track_id},
                         {"position", {l.position.x(), l.position.y(), l.position.z()}},
                         {"descriptor", to_hex(l.descriptor)},
                         {"observations", std::move(observations)}});
  }
  j["landmarks"] = std::move(landmarks);
  common::write_file_atomically(path, j.dump());  // no half-written map on failure
}

Map load_map(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(fmt::format("{}: cannot open the map file", path.string()));
  json j;
  try {
    j = json::parse(in);
  } catch (const json::parse_error& e) {
    throw std::runtime_error(
        fmt::format("{}: expected a JSON edx-slam-map file ({})", path.string(), e.what()));
  }
  const Reader rd(path);
  const json& format = rd.at(j, "map", "format");
  if (!format.is_string() || format.get<std::string>() != kMapFormatName) {
    rd.fail("map.format", fmt::format("\"{}\"", kMapFormatName));
  }
  if (rd.integer(j, "map", "version") != kMapFormatVersion) {
    rd.fail("map.version", fmt::format("{}", kMapFormatVersion));
  }
  Map map;
  const json& source = rd.at(j, "map", "source");
  if (!source.is_string()) rd.fail("map.source", "a string");
  map.source = source.get<std::string>();
  const json& cam = rd.at(j, "map", "camera");
  map.camera.width = static_cast<int>(rd.integer(cam, "map.camera", "width"));
  map.camera.height = static_cast<int>(rd.integer(cam, "map.camera", "height"));
  map.camera.fx = rd.number(cam, "map.camera", "fx");
  map.camera.fy = rd.number(cam, "map.camera", "fy");
  map.camera.cx = rd.number(cam, "map.camera", "cx");
  map.camera.cy = rd.number(cam, "map.camera", "cy");
  map.camera.baseline_m = rd.number(cam, "map.camera", "baseline_m");
  map.camera.T_body_left = rd.pose(cam, "map.camera", "T_body_left");
  if (map.camera.width <= 0 || map.camera.height <= 0 || map.camera.fx <= 0 || map.camera.fy <= 0 ||
      map.camera.baseline_m <= 0) {
    rd.fail("map.camera", "positive width, height, fx, fy and baseline_m");
  }

  std::unordered_map<std::int64_t, std::size_t> keypoint_counts;
  const json& keyframes = rd.array(j, "map", "keyframes");
  for (std::size_t i = 0; i < keyframes.size(); ++i) {
    const std::string where = fmt::format("map.keyframes[{}]", i);
    const json& k = keyframes[i];
    MapKeyframe kf;
    kf.id = rd.integer(k, where, "id");
    kf.t_ns = rd.integer(k, where, "t_ns");
    const std::int64_t frame_index = rd.integer(k, where, "frame_index");
    if (frame_index < 0) rd.fail(where + ".frame_index", "an integer >= 0");
    kf.frame_index = static_cast<std::size_t>(frame_index);
    kf.T_world_body = rd.pose(k, where, "T_world_body");
    if (!keypoint_counts.empty() && keypoint_counts.contains(kf.id)) {
      rd.fail(where + ".id", "a keyframe id not used before");
    }
    const json& keypoints = rd.array(k, where, "keypoints");
    for (std::size_t p = 0; p < keypoints.size(); ++p) {
      const std::string kw = fmt::format("{}.keypoints[{}]", where, p);
      const json& kp = keypoints[p];
      MapKeypoint& point = kf.keypoints.emplace_back();
      point.track_id = rd.integer(kp, kw, "track_id");
      point.left = rd.numbers(rd.at(kp, kw, "left"), kw + ".left", 2);
      const json& right = rd.at(kp, kw, "right");
      if (!right.is_null()) point.right = Eigen::Vector2d(rd.numbers(right, kw + ".right", 2));
      point.depth_m = rd.number(kp, kw, "depth_m");
      point.octave = static_cast<int>(rd.integer(kp, kw, "octave"));
      point.angle_deg = rd.number(kp, kw, "angle");
      point.descriptor = rd.descriptor(kp, kw);
    }
    keypoint_counts[kf.id] = kf.keypoints.size();
    map.keyframes.push_back(std::move(kf));
  }

  std::set<std::int64_t> landmark_ids;
  const json& landmarks = rd.array(j, "map", "landmarks");
  for (std::size_t i = 0; i < landmarks.size(); ++i) {
    const std::string where = fmt::format("map.landmarks[{}]", i);
    const json& l = landmarks[i];
    MapLandmark landmark;
    landmark.id = rd.integer(l, where, "id");
    if (!landmark_ids.insert(landmark.id).second) {
      rd.fail(where + ".id", "a landmark id not used before");
    }
    landmark.track_id = rd.integer(l, where, "track_id");
    landmark.position = rd.numbers(rd.at(l, where, "position"), where + ".position", 3);
    landmark.descriptor = rd.descriptor(l, where);
    const json& observations = rd.array(l, where, "observations");
    for (std::size_t o = 0; o < observations.size(); ++o) {
      const std::string ow = fmt::format("{}.observations[{}]", where, o);
      const json& ob = observations[o];
      if (!ob.is_array() || ob.size() != 2 || !ob[0].is_number_integer() ||
          !ob[1].is_number_integer()) {
        rd.fail(ow, "[keyframe_id, keypoint_index] (two integers)");
      }
      MapObservation obs{ob[0].get<std::int64_t>(), 0};
      const std::int64_t index = ob[1].get<std::int64_t>();
      const auto kf = keypoint_counts.find(obs.keyframe_id);
      if (kf == keypoint_counts.end()) rd.fail(ow, "the id of a keyframe in map.keyframes");
      if (index < 0 || static_cast<std::size_t>(index) >= kf->second) {
        rd.fail(ow, fmt::format("a keypoint index in [0, {}) of keyframe {}", kf->second,
                                obs.keyframe_id));
      }
      obs.keypoint_index = static_cast<std::size_t>(index);
      landmark.observations.push_back(obs);
    }
    map.landmarks.push_back(std::move(landmark));
  }
  return map;
}

}  // namespace edx::backend::slam
