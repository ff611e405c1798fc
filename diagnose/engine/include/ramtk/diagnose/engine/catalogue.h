// The effect catalogue of DESIGN.md: stable names `ramtk diagnose` uses for causes. Names may be
// added, never renamed.
#pragma once

#include <string>
#include <vector>

#include "ramtk/diagnose/engine/diagnosis.h"

namespace ramtk::diagnose {

struct EffectInfo {
  const char* name;         // stable identifier
  DataKind kind;            // the data it shows up in
  const char* description;  // one line for reports
};

// Every catalogued effect, in DESIGN.md order.
const std::vector<EffectInfo>& EffectCatalogue();
// The effects of one data kind.
std::vector<EffectInfo> EffectsOf(DataKind kind);
// True when `name` is a catalogue name (or kNoEffect / kUnexplained).
bool IsKnownCause(const std::string& name);

}  // namespace ramtk::diagnose
