#pragma once
// The command line and the effective options of the running subcommand, as the Provenance that
// every output of the command records (ramtk/core/provenance.h, docs/formats.md#provenance).

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "ramtk/core/provenance.h"

namespace ramtk::tools {

// Keeps argv for CommandProvenance; main calls it once before parsing.
void RecordCommandLine(int argc, char** argv);

// Every option of `command` (positionals and flags included, --help excluded) with its effective
// value: as given on the command line, else its default. Keys are the option names without
// dashes ("min-depth"); values are JSON booleans, numbers or strings (lists as arrays), null for
// an option without a value or default.
nlohmann::json EffectiveOptions(CLI::App* command);

// AddProvenanceInput for `path` when it names a regular file (an option may also take a model
// name such as kr150, or be empty).
void AddProvenanceFile(Provenance* provenance, const std::string& path);

// StartProvenance with the recorded command line and EffectiveOptions(command).
Provenance CommandProvenance(CLI::App* command);

// ProvenanceSidecar written atomically; returns its path.
std::string WriteProvenanceSidecar(const std::string& output_path, const Provenance& provenance);

// Outputs assembled for WriteFilesAtomically, stamped: a JSON object gets the block as its last
// member (WithProvenance); a CSV, YAML or text file gets its sidecar added to `files` (written in
// the same unit); HTML pages and pictures are left as they are (a page gets the block through
// HtmlReport::AddProvenance before it is rendered).
void StampOutputs(std::vector<std::pair<std::string, std::string>>* files, const Provenance& provenance);

}  // namespace ramtk::tools
