#include "ramtk/kinematics/robot_io.h"

#include <cmath>
#include <cstdio>

#include <yaml-cpp/yaml.h>

#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"
#include "ramtk/core/units.h"

namespace ramtk::kinematics {
namespace {

InputLocation At(const std::string& path, const YAML::Node& node, const std::string& field) {
  InputLocation where{path, 0, field};
  if (node.IsDefined() && node.Mark().line >= 0) where.line = node.Mark().line + 1;
  return where;
}

double ReadNumber(const std::string& path, const YAML::Node& parent, const std::string& key,
                  const std::string& field) {
  const YAML::Node node = parent[key];
  if (!node.IsDefined() || node.IsNull()) throw InputError(At(path, parent, field), "missing");
  if (!node.IsScalar()) throw InputError(At(path, node, field), "expected a number");
  double value = 0.0;
  try {
    value = node.as<double>();
  } catch (const YAML::Exception&) {
    throw InputError(At(path, node, field), "expected a number, got '" + node.Scalar() + "'");
  }
  if (!std::isfinite(value)) throw InputError(At(path, node, field), "must be finite");
  return value;
}

std::string ReadString(const std::string& path, const YAML::Node& parent, const std::string& key, bool required) {
  const YAML::Node node = parent[key];
  if (!node.IsDefined() || node.IsNull()) {
    if (required) throw InputError(At(path, parent, key), "missing");
    return {};
  }
  if (!node.IsScalar()) throw InputError(At(path, node, key), "expected text");
  return node.Scalar();
}

}  // namespace

RobotModel ParseRobotModel(const std::string& yaml_text, const std::string& path) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::ParserException& e) {
    throw InputError({path, e.mark.line + 1, ""}, "YAML syntax error: " + e.msg);
  }
  if (!root.IsMap()) throw InputError({path, 1, ""}, "expected a YAML mapping at the top level");

  RobotModel model;
  model.name = ReadString(path, root, "name", true);
  model.source = ReadString(path, root, "source", false);
  const std::string convention = ReadString(path, root, "convention", true);
  if (convention == "dh") {
    model.convention = Convention::kDh;
  } else if (convention == "mdh") {
    model.convention = Convention::kMdh;
  } else {
    throw InputError(At(path, root["convention"], "convention"), "expected 'dh' or 'mdh', got '" + convention + "'");
  }

  const YAML::Node joints = root["joints"];
  if (!joints.IsDefined()) throw InputError(At(path, root, "joints"), "missing");
  if (!joints.IsSequence()) throw InputError(At(path, joints, "joints"), "expected a list of joints");
  if (joints.size() != static_cast<std::size_t>(kNumJoints)) {
    throw InputError(At(path, joints, "joints"),
                     "expected " + std::to_string(kNumJoints) + " joints, got " + std::to_string(joints.size()));
  }
  for (int j = 0; j < kNumJoints; ++j) {
    const YAML::Node jn = joints[j];
    const std::string prefix = "joints[" + std::to_string(j + 1) + "].";
    if (!jn.IsMap()) throw InputError(At(path, jn, "joints[" + std::to_string(j + 1) + "]"), "expected a mapping");
    LinkParams& link = model.links[j];
    link.d = ReadNumber(path, jn, "d", prefix + "d");
    link.theta0 = DegToRad(ReadNumber(path, jn, "theta0", prefix + "theta0"));
    link.a = ReadNumber(path, jn, "a", prefix + "a");
    link.alpha = DegToRad(ReadNumber(path, jn, "alpha", prefix + "alpha"));
    link.beta = jn["beta"].IsDefined() ? DegToRad(ReadNumber(path, jn, "beta", prefix + "beta")) : 0.0;
    JointMapping& map = model.mapping[j];
    map.sign = jn["sign"].IsDefined() ? ReadNumber(path, jn, "sign", prefix + "sign") : 1.0;
    if (map.sign != 1.0 && map.sign != -1.0) {
      throw InputError(At(path, jn["sign"], prefix + "sign"), "must be 1 or -1");
    }
    map.offset = jn["offset"].IsDefined() ? DegToRad(ReadNumber(path, jn, "offset", prefix + "offset")) : 0.0;
  }

  // Structural zeros: all β for DH; listed by name for MDH.
  if (model.convention == Convention::kDh) {
    for (int j = 0; j < kNumJoints; ++j) model.structural_zero[ParamIndex(ParamKind::kBeta, j)] = true;
  }
  const YAML::Node zeros = root["structural_zeros"];
  if (zeros.IsDefined() && !zeros.IsNull()) {
    if (!zeros.IsSequence()) throw InputError(At(path, zeros, "structural_zeros"), "expected a list of parameter names");
    for (std::size_t k = 0; k < zeros.size(); ++k) {
      const std::string field = "structural_zeros[" + std::to_string(k) + "]";
      if (!zeros[k].IsScalar()) throw InputError(At(path, zeros[k], field), "expected a parameter name");
      const int index = ParamIndexFromName(zeros[k].Scalar());
      if (index < 0) {
        throw InputError(At(path, zeros[k], field),
                         "unknown parameter '" + zeros[k].Scalar() + "' (expected d1..d6, theta1.., a1.., alpha1.., beta1..)");
      }
      model.structural_zero[index] = true;
    }
  } else if (model.convention == Convention::kMdh) {
    throw InputError(At(path, root, "structural_zeros"), "missing (an MDH model must state which parameters are zero)");
  }
  const ParamVector params = model.Params();
  for (int k = 0; k < kNumParams; ++k) {
    if (model.structural_zero[k] && params[k] != 0.0) {
      const int j = ParamJointOf(k);
      const std::string kind = ParamName(k).substr(0, ParamName(k).size() - 1);
      throw InputError(At(path, joints[j], "joints[" + std::to_string(j + 1) + "]." + kind),
                       ParamName(k) + " is a structural zero of this model but is " +
                           std::to_string(IsAngleParam(k) ? RadToDeg(params[k]) : params[k]));
    }
  }
  return model;
}

RobotModel ReadRobotModel(const std::string& path) {
  std::string text;
  try {
    text = ReadTextFile(path);
  } catch (const InputError&) {
    throw InputError({path, 0, ""}, "cannot open robot model file");
  }
  return ParseRobotModel(text, path);
}

std::string RobotModelToYaml(const RobotModel& model) {
  YAML::Emitter out;
  out.SetDoublePrecision(17);  // round-trips every double
  out << YAML::BeginMap;
  out << YAML::Key << "name" << YAML::Value << model.name;
  if (!model.source.empty()) out << YAML::Key << "source" << YAML::Value << model.source;
  out << YAML::Key << "convention" << YAML::Value << (model.convention == Convention::kDh ? "dh" : "mdh");
  out << YAML::Key << "joints" << YAML::Value << YAML::BeginSeq;
  for (int j = 0; j < kNumJoints; ++j) {
    const LinkParams& l = model.links[j];
    out << YAML::Flow << YAML::BeginMap;
    out << YAML::Key << "d" << YAML::Value << l.d;
    out << YAML::Key << "theta0" << YAML::Value << RadToDeg(l.theta0);
    out << YAML::Key << "a" << YAML::Value << l.a;
    out << YAML::Key << "alpha" << YAML::Value << RadToDeg(l.alpha);
    out << YAML::Key << "beta" << YAML::Value << RadToDeg(l.beta);
    out << YAML::Key << "sign" << YAML::Value << static_cast<int>(model.mapping[j].sign);
    out << YAML::Key << "offset" << YAML::Value << RadToDeg(model.mapping[j].offset);
    out << YAML::EndMap;
  }
  out << YAML::EndSeq;
  out << YAML::Key << "structural_zeros" << YAML::Value << YAML::Flow << YAML::BeginSeq;
  for (int k = 0; k < kNumParams; ++k) {
    if (model.structural_zero[k]) out << ParamName(k);
  }
  out << YAML::EndSeq << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

void WriteRobotModel(const RobotModel& model, const std::string& path) {
  WriteFileAtomically(path, RobotModelToYaml(model));
}

}  // namespace ramtk::kinematics
