#include "ramtk/diagnose/engine/catalogue.h"

#include <algorithm>
#include <sstream>

namespace ramtk::diagnose {
namespace {

std::vector<EffectInfo>& Catalogue() {
  static std::vector<EffectInfo> catalogue = {
#define RAMTK_FRINGE_CAUSE(name, fit, lo, hi, either_sign, visible, parameters, plausible, help) \
  {#name, DataKind::kFringe, help, parameters, plausible},
#include "ramtk/diagnose/engine/fringe_causes.def"
#define RAMTK_ROBOT_CAUSE(name, code, parameters, plausible, help) {#name, DataKind::kRobot, help, parameters, plausible},
#include "ramtk/diagnose/engine/robot_causes.def"
#define RAMTK_LASER_CAUSE(name, drawn, fitted, parameters, plausible, help) \
  {#name, DataKind::kLaser, help, parameters, plausible},
#include "ramtk/diagnose/engine/laser_causes.def"
  };
  return catalogue;
}

}  // namespace

const std::vector<EffectInfo>& EffectCatalogue() { return Catalogue(); }

std::vector<EffectInfo> EffectsOf(DataKind kind) {
  std::vector<EffectInfo> out;
  for (const EffectInfo& e : EffectCatalogue())
    if (e.kind == kind) out.push_back(e);
  return out;
}

bool IsKnownCause(const std::string& name) {
  if (name == kNoEffect || name == kUnexplained || name == kAmbiguous || name == kNotObservable || name == kImplausible) {
    return true;
  }
  for (const EffectInfo& e : EffectCatalogue())
    if (name == e.name) return true;
  return false;
}

void RegisterEffect(const EffectInfo& info) {
  if (!IsKnownCause(info.name)) Catalogue().push_back(info);
}

std::string CatalogueMarkdown() {
  std::ostringstream o;
  o << "| cause | kind | fitted values | plausible | what it means |\n|---|---|---|---|---|\n";
  for (const EffectInfo& e : EffectCatalogue()) {
    o << "| `" << e.name << "` | " << DataKindName(e.kind) << " | " << e.parameters << " | " << e.plausible << " | "
      << e.description << " |\n";
  }
  return o.str();
}

std::string CatalogueHelp(DataKind kind) {
  size_t width = 0;
  for (const EffectInfo& e : EffectsOf(kind)) width = std::max(width, std::string(e.name).size());
  std::ostringstream o;
  for (const EffectInfo& e : EffectsOf(kind))
    o << "  " << e.name << std::string(width + 2 - std::string(e.name).size(), ' ') << e.description << "\n";
  return o.str();
}

}  // namespace ramtk::diagnose
