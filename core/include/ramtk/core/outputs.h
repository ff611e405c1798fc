#pragma once
// Output safety (issue 17). Every output is written beside its target under a temporary name and
// moved into place only when complete, so an error or an interruption never leaves a
// half-written result, and `--force` replaces an old result only once the new one exists.
// Temporaries in flight are registered so that SIGINT / SIGTERM can remove them
// (InstallInterruptCleanup, called once by a program's main). Outputs are checked against the
// inputs: an output may not be, or contain, one of the run's inputs, and two outputs of one run
// may not be the same path.

#include <filesystem>
#include <string>
#include <vector>

namespace ramtk {

// Registry of temporary files and folders being written (thread-safe). Paths still registered
// when the process is interrupted are removed by the interrupt handler.
void RegisterTemporary(const std::filesystem::path& path);
void UnregisterTemporary(const std::filesystem::path& path);
// Removes every registered temporary (files and folders); returns how many existed.
int RemoveRegisteredTemporaries();

// Blocks SIGINT, SIGTERM and SIGHUP in the calling thread (and so in every thread it starts
// later) and starts a thread that waits for them: on a signal it removes the registered
// temporaries, writes one line to stderr and ends the process with 128 + the signal number. Call
// first thing in main, before any other thread exists. Idempotent.
void InstallInterruptCleanup(const std::string& program_name);

// InputError when `output` is the same path as one of `inputs`, is a folder that contains one of
// them, or (for folder outputs) lies inside an input folder that would be replaced. `field` names
// the output option in the error. Paths that do not exist yet are compared lexically after
// resolving the existing part (std::filesystem::weakly_canonical).
void CheckOutputAgainstInputs(const std::string& output, const std::vector<std::string>& inputs,
                              const std::string& field);
// InputError when two of the named outputs (option name, path) are the same path or one folder
// contains another output. Empty paths are skipped.
void CheckOutputsDistinct(const std::vector<std::pair<std::string, std::string>>& named_outputs);

// A folder of outputs written as a unit. The constructor checks the target (an existing
// non-empty target needs `overwrite`; its parent must exist) and creates a sibling temporary
// folder "<target>.partial-<pid>" to write into; Commit() moves the old target aside, moves the
// temporary into place and then removes the old one. Destroyed without Commit() (an error, a
// cancellation), it removes the temporary and leaves the old target untouched.
class StagedFolder {
 public:
  // `field` names the option in errors ("--out").
  StagedFolder(const std::string& target, bool overwrite, const std::string& field = "--out");
  ~StagedFolder();
  StagedFolder(const StagedFolder&) = delete;
  StagedFolder& operator=(const StagedFolder&) = delete;

  // The temporary folder to write into.
  const std::filesystem::path& path() const { return tmp_; }
  const std::filesystem::path& target() const { return target_; }
  void Commit();

 private:
  std::filesystem::path target_;
  std::filesystem::path tmp_;
  std::string field_;
  bool committed_ = false;
};

}  // namespace ramtk
