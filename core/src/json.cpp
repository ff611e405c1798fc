#include "ramtk/core/json.h"

#include <cmath>
#include <set>
#include <vector>

#include "ramtk/core/units.h"

namespace ramtk {

nlohmann::json ParseJsonText(const std::string& text, const std::string& path) {
  // nlohmann keeps the last of two equal keys; a file that says a value twice is refused instead.
  std::vector<std::set<std::string>> keys;  // the keys seen in each object being parsed
  const nlohmann::json::parser_callback_t once = [&](int, nlohmann::json::parse_event_t event, nlohmann::json& parsed) {
    using Event = nlohmann::json::parse_event_t;
    if (event == Event::object_start) {
      keys.emplace_back();
    } else if (event == Event::object_end) {
      if (!keys.empty()) keys.pop_back();
    } else if (event == Event::key && !keys.empty()) {
      const std::string key = parsed.get<std::string>();
      if (!keys.back().insert(key).second)
        throw InputError({path, 0, key}, "duplicate key: an object gives it twice (which value is meant?)");
    }
    return true;
  };
  try {
    return nlohmann::json::parse(text, once);
  } catch (const nlohmann::json::exception& e) {  // parse_error, or out_of_range for 1e999
    throw InputError({path, 0, ""}, std::string("not valid JSON: ") + e.what());
  }
}

const nlohmann::json& JsonRequire(const nlohmann::json& object, const std::string& key, const std::string& path,
                                  const std::string& where) {
  if (!object.is_object() || !object.contains(key)) throw InputError({path, 0, where + key}, "missing key");
  return object.at(key);
}

double JsonNumber(const nlohmann::json& value, const std::string& path, const std::string& field) {
  if (!value.is_number()) throw InputError({path, 0, field}, "expected a number, got " + value.dump());
  const double v = value.get<double>();
  if (!std::isfinite(v)) throw InputError({path, 0, field}, "expected a finite number");
  return v;
}

int JsonInt(const nlohmann::json& value, const std::string& path, const std::string& field) {
  const double v = JsonNumber(value, path, field);
  if (v != std::floor(v) || std::abs(v) > 1e9)
    throw InputError({path, 0, field}, "expected an integer, got " + value.dump());
  return static_cast<int>(v);
}

Vec3 JsonVec3(const nlohmann::json& value, const std::string& path, const std::string& field) {
  if (!value.is_array() || value.size() != 3) throw InputError({path, 0, field}, "expected an array of 3 numbers");
  Vec3 v;
  for (int i = 0; i < 3; ++i) {
    if (!value[i].is_number()) throw InputError({path, 0, field}, "expected an array of 3 numbers");
    v[i] = value[i].get<double>();
    if (!std::isfinite(v[i])) throw InputError({path, 0, field}, "expected finite numbers");
  }
  return v;
}

nlohmann::json Vec3ToJson(const Vec3& v) { return nlohmann::json::array({v.x(), v.y(), v.z()}); }

double JsonNumberAt(const nlohmann::json& object, const std::string& key, const std::string& path,
                    const std::string& where) {
  return JsonNumber(JsonRequire(object, key, path, where), path, where + key);
}

Vec3 JsonVec3At(const nlohmann::json& object, const std::string& key, const std::string& path,
                const std::string& where) {
  return JsonVec3(JsonRequire(object, key, path, where), path, where + key);
}

namespace {

Isometry3 PoseFromRows(const nlohmann::json& rows, const std::string& path, const std::string& field,
                       double max_orthonormality_error) {
  if (!rows.is_array() || (rows.size() != 3 && rows.size() != 4))
    throw InputError({path, 0, field}, "expected 3 or 4 rows of 4 numbers");
  Mat4 m = Mat4::Identity();
  for (std::size_t r = 0; r < rows.size(); ++r) {
    if (!rows[r].is_array() || rows[r].size() != 4) throw InputError({path, 0, field}, "every row needs 4 numbers");
    for (int c = 0; c < 4; ++c) {
      if (!rows[r][c].is_number()) throw InputError({path, 0, field}, "entries must be numbers");
      m(static_cast<int>(r), c) = rows[r][c].get<double>();
      if (!std::isfinite(m(static_cast<int>(r), c))) throw InputError({path, 0, field}, "entries must be finite");
    }
  }
  if (rows.size() == 4 && (m.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-9)
    throw InputError({path, 0, field}, "the last row of a 4x4 transform must be [0, 0, 0, 1]");
  const Mat3 rotation = m.topLeftCorner<3, 3>();
  const double error = OrthonormalityError(rotation);
  if (!(error <= max_orthonormality_error)) {
    throw InputError({path, 0, field}, "rotation part is not orthonormal (error " + std::to_string(error) + ")");
  }
  Isometry3 t = Isometry3::Identity();
  t.linear() = NearestRotation(rotation);
  t.translation() = m.block<3, 1>(0, 3);
  return t;
}

}  // namespace

Isometry3 JsonPose(const nlohmann::json& value, const std::string& path, const std::string& field,
                   double max_orthonormality_error) {
  if (value.is_array()) return PoseFromRows(value, path, field, max_orthonormality_error);
  if (value.is_object() && value.contains("position_mm")) {
    Isometry3 pose = Isometry3::Identity();
    pose.translation() = JsonVec3(value.at("position_mm"), path, field + ".position_mm");
    const Vec3 abc = JsonVec3(JsonRequire(value, "abc_deg", path, field + "."), path, field + ".abc_deg");
    pose.linear() = RotationFromKukaAbc({DegToRad(abc.x()), DegToRad(abc.y()), DegToRad(abc.z())});
    return pose;
  }
  if (value.is_object() && value.contains("matrix"))
    return PoseFromRows(value.at("matrix"), path, field + ".matrix", max_orthonormality_error);
  throw InputError({path, 0, field},
                   "expected a pose: {\"position_mm\": [x,y,z], \"abc_deg\": [A,B,C]}, {\"matrix\": rows} or "
                   "3-4 rows of [r r r t]");
}

Isometry3 JsonPoseAt(const nlohmann::json& object, const std::string& key, const std::string& path,
                     const std::string& where) {
  return JsonPose(JsonRequire(object, key, path, where), path, where + key);
}

nlohmann::json PoseToJson(const Isometry3& pose) {
  const KukaAbc abc = KukaAbcFromRotation(pose.linear());
  nlohmann::json j;
  j["position_mm"] = Vec3ToJson(pose.translation());
  j["abc_deg"] = {RadToDeg(abc.a), RadToDeg(abc.b), RadToDeg(abc.c)};
  nlohmann::json m = nlohmann::json::array();
  for (int r = 0; r < 4; ++r)
    m.push_back({pose.matrix()(r, 0), pose.matrix()(r, 1), pose.matrix()(r, 2), pose.matrix()(r, 3)});
  j["matrix"] = m;
  return j;
}

}  // namespace ramtk
