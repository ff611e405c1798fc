#include "ramtk/kinematics/robot_io.h"

#include <cmath>
#include <cstdio>

#include <yaml-cpp/yaml.h>

#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"
#include "ramtk/core/units.h"
#include "ramtk/core/yaml.h"

namespace ramtk::kinematics {
namespace {

const char* const kKindWords[] = {"d", "theta0", "a", "alpha", "beta"};

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

Vec3 ReadVec3(const std::string& path, const YAML::Node& parent, const std::string& key, const std::string& field) {
  const YAML::Node node = parent[key];
  if (!node.IsSequence() || node.size() != 3) throw InputError(At(path, node.IsDefined() ? node : parent, field), "expected [x, y, z]");
  Vec3 v;
  for (int k = 0; k < 3; ++k) {
    try {
      v[k] = node[k].as<double>();
    } catch (const YAML::Exception&) {
      throw InputError(At(path, node, field), "expected a number, got '" + node[k].Scalar() + "'");
    }
    if (!std::isfinite(v[k])) throw InputError(At(path, node, field), "must be finite");
  }
  return v;
}

// A mass (kg, ≥ 0) and its centre (mm): {mass: 28.3, com: [0, 0, 150]}.
LinkMass ReadMass(const std::string& path, const YAML::Node& node, const std::string& prefix) {
  LinkMass m;
  m.mass_kg = ReadNumber(path, node, "mass", prefix + "mass");
  if (m.mass_kg < 0.0 || m.mass_kg > 1e5) throw InputError(At(path, node["mass"], prefix + "mass"), "must be in 0..1e5 kg");
  m.com_mm = node["com"].IsDefined() ? ReadVec3(path, node, "com", prefix + "com") : Vec3::Zero();
  return m;
}

void ReadGravityData(const std::string& path, const YAML::Node& root, const YAML::Node& joints, RobotChain* chain) {
  const int n = chain->NumJoints();
  int with_mass = 0;
  for (int j = 0; j < n; ++j) with_mass += joints[j]["mass"].IsDefined() ? 1 : 0;
  if (with_mass != 0 && with_mass != n) {
    throw InputError(At(path, joints, "joints"), "either every joint or none has a 'mass' (" + std::to_string(with_mass) +
                                                     " of " + std::to_string(n) + " have one)");
  }
  if (with_mass == n) {
    for (int j = 0; j < n; ++j) chain->masses.push_back(ReadMass(path, joints[j], "joints[" + std::to_string(j + 1) + "]."));
  }
  if (root["payload"].IsDefined()) {
    if (!root["payload"].IsMap()) throw InputError(At(path, root["payload"], "payload"), "expected {mass, com}");
    chain->payload = ReadMass(path, root["payload"], "payload.");
  }
  if (root["gravity"].IsDefined()) {
    const Vec3 g = ReadVec3(path, root, "gravity", "gravity");
    if (g.norm() < 1e-9) throw InputError(At(path, root["gravity"], "gravity"), "must not be zero");
    chain->gravity_in_base = g.normalized();
  }
}

}  // namespace

RobotChain ParseRobotChain(const std::string& yaml_text, const std::string& path) {
  const YAML::Node root = LoadYamlText(yaml_text, path);
  if (!root.IsMap()) throw InputError({path, 1, ""}, "expected a YAML mapping at the top level");

  RobotChain chain;
  chain.name = ReadString(path, root, "name", true);
  chain.source = ReadString(path, root, "source", false);
  const std::string convention = ReadString(path, root, "convention", true);
  if (convention == "dh") {
    chain.convention = Convention::kDh;
  } else if (convention == "mdh") {
    chain.convention = Convention::kMdh;
  } else {
    throw InputError(At(path, root["convention"], "convention"), "expected 'dh' or 'mdh', got '" + convention + "'");
  }

  const YAML::Node joints = root["joints"];
  if (!joints.IsDefined()) throw InputError(At(path, root, "joints"), "missing");
  if (!joints.IsSequence()) throw InputError(At(path, joints, "joints"), "expected a list of joints");
  if (joints.size() < 1 || joints.size() > static_cast<std::size_t>(kMaxChainJoints)) {
    throw InputError(At(path, joints, "joints"), "expected 1.." + std::to_string(kMaxChainJoints) + " joints, got " +
                                                     std::to_string(joints.size()));
  }
  const int n = static_cast<int>(joints.size());
  chain.links.resize(n);
  chain.mapping.resize(n);
  for (int j = 0; j < n; ++j) {
    const YAML::Node jn = joints[j];
    const std::string prefix = "joints[" + std::to_string(j + 1) + "].";
    if (!jn.IsMap()) throw InputError(At(path, jn, "joints[" + std::to_string(j + 1) + "]"), "expected a mapping");
    LinkParams& link = chain.links[j];
    link.d = ReadNumber(path, jn, "d", prefix + "d");
    link.theta0 = DegToRad(ReadNumber(path, jn, "theta0", prefix + "theta0"));
    link.a = ReadNumber(path, jn, "a", prefix + "a");
    link.alpha = DegToRad(ReadNumber(path, jn, "alpha", prefix + "alpha"));
    link.beta = jn["beta"].IsDefined() ? DegToRad(ReadNumber(path, jn, "beta", prefix + "beta")) : 0.0;
    JointMapping& map = chain.mapping[j];
    map.sign = jn["sign"].IsDefined() ? ReadNumber(path, jn, "sign", prefix + "sign") : 1.0;
    if (map.sign != 1.0 && map.sign != -1.0) {
      throw InputError(At(path, jn["sign"], prefix + "sign"), "must be 1 or -1");
    }
    map.offset = jn["offset"].IsDefined() ? DegToRad(ReadNumber(path, jn, "offset", prefix + "offset")) : 0.0;
  }
  ReadGravityData(path, root, joints, &chain);

  // Structural zeros: all β for DH; listed by name for MDH.
  chain.structural_zero.assign(chain.NumParams(), false);
  if (chain.convention == Convention::kDh) {
    for (int j = 0; j < n; ++j) chain.structural_zero[ChainParamIndex(ParamKind::kBeta, j)] = true;
  }
  const YAML::Node zeros = root["structural_zeros"];
  if (zeros.IsDefined() && !zeros.IsNull()) {
    if (!zeros.IsSequence()) throw InputError(At(path, zeros, "structural_zeros"), "expected a list of parameter names");
    for (std::size_t k = 0; k < zeros.size(); ++k) {
      const std::string field = "structural_zeros[" + std::to_string(k) + "]";
      if (!zeros[k].IsScalar()) throw InputError(At(path, zeros[k], field), "expected a parameter name");
      const int index = ChainParamIndexFromName(zeros[k].Scalar(), n);
      if (index < 0) {
        throw InputError(At(path, zeros[k], field), "unknown parameter '" + zeros[k].Scalar() + "' (expected d1..d" +
                                                        std::to_string(n) + ", theta1.., a1.., alpha1.., beta1..)");
      }
      chain.structural_zero[index] = true;
    }
  } else if (chain.convention == Convention::kMdh) {
    throw InputError(At(path, root, "structural_zeros"), "missing (an MDH model must state which parameters are zero)");
  }
  const Eigen::VectorXd params = chain.Params();
  for (int k = 0; k < chain.NumParams(); ++k) {
    if (chain.structural_zero[k] && params[k] != 0.0) {
      const int j = k / kParamsPerLink;
      const std::string kind = kKindWords[k % kParamsPerLink];
      throw InputError(At(path, joints[j], "joints[" + std::to_string(j + 1) + "]." + kind),
                       ChainParamName(k) + " is a structural zero of this model but is " +
                           std::to_string(IsChainAngleParam(k) ? RadToDeg(params[k]) : params[k]));
    }
  }
  return chain;
}

RobotModel ParseRobotModel(const std::string& yaml_text, const std::string& path) {
  const RobotChain chain = ParseRobotChain(yaml_text, path);
  if (chain.NumJoints() != kNumJoints) {
    YAML::Node root = YAML::Load(yaml_text);
    throw InputError(At(path, root["joints"], "joints"), "expected " + std::to_string(kNumJoints) + " joints, got " +
                                                             std::to_string(chain.NumJoints()) +
                                                             " (this command handles 6-joint robots; `calib robot` any)");
  }
  return RobotModelFromChain(chain, path);
}

RobotChain ReadRobotChain(const std::string& path) {
  std::string text;
  try {
    text = ReadTextFile(path);
  } catch (const InputError& e) {
    throw InputError({path, 0, ""}, "cannot open robot model file: " + e.message());
  }
  return ParseRobotChain(text, path);
}

RobotModel ReadRobotModel(const std::string& path) {
  std::string text;
  try {
    text = ReadTextFile(path);
  } catch (const InputError& e) {
    throw InputError({path, 0, ""}, "cannot open robot model file: " + e.message());
  }
  return ParseRobotModel(text, path);
}

std::string RobotChainToYaml(const RobotChain& chain) {
  YAML::Emitter out;
  out.SetDoublePrecision(17);  // round-trips every double
  out << YAML::BeginMap;
  out << YAML::Key << "name" << YAML::Value << chain.name;
  if (!chain.source.empty()) out << YAML::Key << "source" << YAML::Value << chain.source;
  out << YAML::Key << "convention" << YAML::Value << (chain.convention == Convention::kDh ? "dh" : "mdh");
  out << YAML::Key << "joints" << YAML::Value << YAML::BeginSeq;
  for (int j = 0; j < chain.NumJoints(); ++j) {
    const LinkParams& l = chain.links[j];
    out << YAML::Flow << YAML::BeginMap;
    out << YAML::Key << "d" << YAML::Value << l.d;
    out << YAML::Key << "theta0" << YAML::Value << RadToDeg(l.theta0);
    out << YAML::Key << "a" << YAML::Value << l.a;
    out << YAML::Key << "alpha" << YAML::Value << RadToDeg(l.alpha);
    out << YAML::Key << "beta" << YAML::Value << RadToDeg(l.beta);
    out << YAML::Key << "sign" << YAML::Value << static_cast<int>(chain.mapping[j].sign);
    out << YAML::Key << "offset" << YAML::Value << RadToDeg(chain.mapping[j].offset);
    if (chain.HasMasses()) {
      out << YAML::Key << "mass" << YAML::Value << chain.masses[j].mass_kg;
      const Vec3& c = chain.masses[j].com_mm;
      out << YAML::Key << "com" << YAML::Value << YAML::Flow << YAML::BeginSeq << c.x() << c.y() << c.z() << YAML::EndSeq;
    }
    out << YAML::EndMap;
  }
  out << YAML::EndSeq;
  if (chain.payload.mass_kg > 0.0) {
    const Vec3& c = chain.payload.com_mm;
    out << YAML::Key << "payload" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "mass" << YAML::Value
        << chain.payload.mass_kg << YAML::Key << "com" << YAML::Value << YAML::Flow << YAML::BeginSeq << c.x() << c.y()
        << c.z() << YAML::EndSeq << YAML::EndMap;
  }
  if (chain.gravity_in_base != Vec3(0, 0, -1)) {
    const Vec3& g = chain.gravity_in_base;
    out << YAML::Key << "gravity" << YAML::Value << YAML::Flow << YAML::BeginSeq << g.x() << g.y() << g.z() << YAML::EndSeq;
  }
  out << YAML::Key << "structural_zeros" << YAML::Value << YAML::Flow << YAML::BeginSeq;
  for (int k = 0; k < chain.NumParams(); ++k) {
    if (chain.structural_zero[k]) out << ChainParamName(k);
  }
  out << YAML::EndSeq << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

std::string RobotModelToYaml(const RobotModel& model) { return RobotChainToYaml(ChainFromRobotModel(model)); }

void WriteRobotChain(const RobotChain& chain, const std::string& path) {
  WriteFileAtomically(path, RobotChainToYaml(chain));
}

void WriteRobotModel(const RobotModel& model, const std::string& path) {
  WriteFileAtomically(path, RobotModelToYaml(model));
}

}  // namespace ramtk::kinematics
