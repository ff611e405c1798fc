#pragma once
// JSON in ramtk files: checked getters whose errors name the file and the key path, and the one
// way poses are written and read.
//
// A pose (a rigid transform target_from_source, mm) is written as
//   {"position_mm": [x, y, z], "abc_deg": [A, B, C], "matrix": [[4 numbers] x 4]}
// (KUKA A,B,C: R = RotZ(A)·RotY(B)·RotX(C)). It is read from the first of these that is present:
//   {"position_mm": [x, y, z], "abc_deg": [A, B, C]}  (a "matrix" beside them is ignored)
//   {"matrix": [[r r r t] x 3 or 4]}
//   [[r r r t] x 3 or 4]                              (the rows alone, as hand-written set-ups have)
// A matrix's rotation must be orthonormal to `max_orthonormality_error` and is then replaced by
// the nearest rotation (files print a few decimals).

#include <nlohmann/json.hpp>
#include <string>

#include "ramtk/core/error.h"
#include "ramtk/core/rotation.h"

namespace ramtk {

// The text as JSON; InputError naming `path` ("not valid JSON: ...", also for numbers like 1e999).
nlohmann::json ParseJsonText(const std::string& text, const std::string& path);

// object[key]; InputError "missing key" at field `where` + key when `object` is not an object or
// lacks the key.
const nlohmann::json& JsonRequire(const nlohmann::json& object, const std::string& key, const std::string& path,
                                  const std::string& where = "");
// A finite number / an integer (|n| ≤ 1e9) / three finite numbers; InputError at `field`.
double JsonNumber(const nlohmann::json& value, const std::string& path, const std::string& field);
int JsonInt(const nlohmann::json& value, const std::string& path, const std::string& field);
Vec3 JsonVec3(const nlohmann::json& value, const std::string& path, const std::string& field);
nlohmann::json Vec3ToJson(const Vec3& v);
// The same for object[key], the field named `where` + key.
double JsonNumberAt(const nlohmann::json& object, const std::string& key, const std::string& path,
                    const std::string& where = "");
Vec3 JsonVec3At(const nlohmann::json& object, const std::string& key, const std::string& path,
                const std::string& where = "");

// The pose at `field` in any of the forms above; InputError naming the file and field.
Isometry3 JsonPose(const nlohmann::json& value, const std::string& path, const std::string& field,
                   double max_orthonormality_error = 1e-3);
Isometry3 JsonPoseAt(const nlohmann::json& object, const std::string& key, const std::string& path,
                     const std::string& where = "");
// The pose as {"position_mm", "abc_deg", "matrix"}.
nlohmann::json PoseToJson(const Isometry3& pose);

}  // namespace ramtk
