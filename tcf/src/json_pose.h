#pragma once
// Private JSON helpers of the tcf module: poses as {"position_mm": [x,y,z], "abc_deg": [A,B,C]}
// (KUKA A,B,C: R = RotZ(A)·RotY(B)·RotX(C)), vectors as [x,y,z]; errors name the file and key.

#include <nlohmann/json.hpp>
#include <string>

#include "ramtk/core/error.h"
#include "ramtk/core/rotation.h"
#include "ramtk/core/units.h"

namespace ramtk::tcf::detail {

inline nlohmann::json VecToJson(const Vec3& v) { return nlohmann::json::array({v.x(), v.y(), v.z()}); }

inline nlohmann::json PoseToJson(const Isometry3& pose) {
  const KukaAbc abc = KukaAbcFromRotation(pose.linear());
  nlohmann::json j;
  j["position_mm"] = VecToJson(pose.translation());
  j["abc_deg"] = {RadToDeg(abc.a), RadToDeg(abc.b), RadToDeg(abc.c)};
  nlohmann::json m = nlohmann::json::array();
  for (int r = 0; r < 4; ++r)
    m.push_back({pose.matrix()(r, 0), pose.matrix()(r, 1), pose.matrix()(r, 2), pose.matrix()(r, 3)});
  j["matrix"] = m;
  return j;
}

inline const nlohmann::json& Require(const nlohmann::json& j, const std::string& key, const std::string& path,
                                     const std::string& where) {
  if (!j.is_object() || !j.contains(key)) throw InputError({path, 0, where + key}, "missing key");
  return j.at(key);
}

inline double NumberFrom(const nlohmann::json& j, const std::string& key, const std::string& path,
                         const std::string& where) {
  const nlohmann::json& v = Require(j, key, path, where);
  if (!v.is_number()) throw InputError({path, 0, where + key}, "expected a number");
  return v.get<double>();
}

inline Vec3 VecFrom(const nlohmann::json& j, const std::string& key, const std::string& path,
                    const std::string& where) {
  const nlohmann::json& v = Require(j, key, path, where);
  if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() || !v[2].is_number())
    throw InputError({path, 0, where + key}, "expected an array of 3 numbers");
  return Vec3(v[0].get<double>(), v[1].get<double>(), v[2].get<double>());
}

inline Isometry3 PoseFrom(const nlohmann::json& j, const std::string& key, const std::string& path,
                          const std::string& where) {
  const nlohmann::json& p = Require(j, key, path, where);
  const std::string w = where + key + ".";
  Isometry3 pose = Isometry3::Identity();
  pose.translation() = VecFrom(p, "position_mm", path, w);
  const Vec3 abc = VecFrom(p, "abc_deg", path, w);
  pose.linear() = RotationFromKukaAbc({DegToRad(abc.x()), DegToRad(abc.y()), DegToRad(abc.z())});
  return pose;
}

inline nlohmann::json ParseJson(const std::string& text, const std::string& path) {
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {  // parse_error, or out_of_range for 1e999
    throw InputError({path, 0, ""}, std::string("invalid JSON: ") + e.what());
  }
}

}  // namespace ramtk::tcf::detail
