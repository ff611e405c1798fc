#pragma once
// How an output was made: the ramtk version and git commit, the command line, the effective
// options, the input files with their hashes (XXH3-128), and the run's circumstances (start time, host,
// working folder, elapsed time). Every summary/result JSON and report ramtk writes carries this
// block as its member "provenance" (docs/formats.md#provenance). The command line and options are
// filled by the program (tools/); a library writer receives a Provenance value and never reads
// argv or globals itself.
//
// Everything in the block except its "run" member is a pure function of the inputs, the options
// and the version; "run" (started_utc, host, working_directory, elapsed_s) is the part a
// comparison of two runs drops.

#include <chrono>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace ramtk {

// The ramtk version (CMake's project version) and the git commit the build was configured at
// ("unknown" outside a git checkout). From one generated source file (build_info.cpp).
std::string RamtkVersion();
std::string RamtkGitCommit();

struct ProvenanceInput {
  std::string path;       // as given (relative paths against the run's working folder)
  std::string xxh3_128;   // lower-case hex of the file's XXH3-128 (as `xxhsum -H2` prints it)
  std::uintmax_t bytes = 0;
};

struct Provenance {
  std::string version = RamtkVersion();    // ramtk version
  std::string git_commit = RamtkGitCommit();  // commit of the build ("unknown" without git)
  std::vector<std::string> command;        // the command line, argv[0] first ("" when not known)
  nlohmann::json options = nlohmann::json::object();  // every option's effective value, defaults included
  std::vector<ProvenanceInput> inputs;     // input files with their hashes, in the order added
  // The run group (excluded when comparing two runs):
  std::string started_utc;        // ISO 8601, e.g. 2026-11-29T09:10:11Z
  std::string host;               // gethostname
  std::string working_directory;  // where relative paths in `command` are resolved
  std::chrono::steady_clock::time_point started = std::chrono::steady_clock::now();  // for elapsed_s
};

// A Provenance for a run starting now: version, commit, start time, host and working folder
// filled, with `command` and `options` as given.
Provenance StartProvenance(std::vector<std::string> command, nlohmann::json options);

// Adds `path` with its XXH3-128 and size. A path already listed is not added again. InputError
// naming the file when it cannot be read (RequireRegularFile).
// `recorded_as` (when not empty) is the path written instead of `path` (a path relative to an
// output folder, for a file read through another path).
void AddProvenanceInput(Provenance* provenance, const std::string& path, const std::string& recorded_as = "");

// XXH3-128 of a file's bytes (xxHash; read in 1 MiB blocks) as lower-case hex, the digest
// `xxhsum -H2` prints; InputError naming the file when it cannot be read. A fast non-cryptographic
// hash (tens of GB/s): it tells whether an input changed, it does not authenticate it.
std::string Xxh3OfFile(const std::string& path);
// XXH3-128 of bytes as lower-case hex.
std::string Xxh3Of(const std::string& bytes);

// The block: {"ramtk_version", "git_commit", "command", "options", "inputs": [{"path", "xxh3_128",
// "bytes"}], "run": {"started_utc", "host", "working_directory", "elapsed_s"}}; elapsed_s is the
// time since `started` when this is called.
nlohmann::ordered_json ProvenanceToJson(const Provenance& provenance);

// `json_text` (a JSON object as ramtk writes it: indented by 2, ending in "}\n") with the block
// appended as its last member "provenance", indented to match; the text before it is unchanged.
// Text that is not an object is returned unchanged.
std::string WithProvenance(const std::string& json_text, const Provenance& provenance);

// The provenance of an output that has no place for it (a CSV, a YAML file read by other tools):
// the path `<output without its extension>.provenance.json` and its text {"format":
// "ramtk-provenance", "version": 1, "describes": "<file name>", "provenance": {...}}.
std::pair<std::string, std::string> ProvenanceSidecar(const std::string& output_path, const Provenance& provenance);
// One sidecar for several files of a folder that other commands read as data (a simulator's
// outputs): `folder`/provenance.json, "describes" listing `names`.
std::pair<std::string, std::string> FolderProvenance(const std::string& folder, const std::vector<std::string>& names,
                                                     const Provenance& provenance);
// Writes FolderProvenance for every regular file under `folder` (paths relative to it, sorted,
// "provenance.json" itself left out), atomically; for a folder written as a unit, call it before
// the folder is committed.
void WriteFolderProvenance(const std::string& folder, const Provenance& provenance);

// The block as Markdown: a "## Provenance" section (version, commit, command line, inputs, run)
// with the options as a JSON code block.
std::string ProvenanceMarkdown(const Provenance& provenance);

// The command line as one shell line (arguments with spaces or shell characters single-quoted).
std::string ShellCommandLine(const std::vector<std::string>& command);

}  // namespace ramtk
