// The effect catalogue: stable names `ramtk diagnose` uses for causes, one row per cause in the
// kinds' tables (robot_causes.def, fringe_causes.def, laser_causes.def beside this header). Names
// may be added, never renamed.
#pragma once

#include <string>
#include <vector>

#include "ramtk/diagnose/engine/diagnosis.h"

namespace ramtk::diagnose {

struct EffectInfo {
  const char* name;         // stable identifier
  DataKind kind;            // the data it shows up in
  const char* description;  // one line for reports
  const char* parameters;   // the fitted values it reports ("" when it is not fitted)
  const char* plausible;    // physical bounds of the fitted values ("" when none)
};

// Every catalogued effect: the fringe rows, the robot rows, the laser rows, each in its table's
// order, then the ones added with RegisterEffect.
const std::vector<EffectInfo>& EffectCatalogue();
// The effects of one data kind.
std::vector<EffectInfo> EffectsOf(DataKind kind);
// True when `name` is a catalogue name (or kNoEffect / kUnexplained).
bool IsKnownCause(const std::string& name);
// Adds an effect to the catalogue (a cause registered outside the tables, e.g. by a test); the
// strings must outlive the catalogue. Ignored when the name is already catalogued.
void RegisterEffect(const EffectInfo& info);
// The catalogue as a Markdown table (| cause | kind | fitted values | plausible | what it means |),
// the table docs/diagnose.md carries.
std::string CatalogueMarkdown();
// One line per cause of `kind` ("  name  description"), for command-line help.
std::string CatalogueHelp(DataKind kind);

}  // namespace ramtk::diagnose
