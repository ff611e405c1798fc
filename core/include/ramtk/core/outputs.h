#pragma once
// Output safety. Every output is written beside its target under a temporary name and
// moved into place only when complete, so an error or an interruption never leaves a
// half-written result, and `--force` replaces an old result only once the new one exists.
// Temporaries in flight are registered so that SIGINT / SIGTERM can remove them
// (InstallInterruptCleanup, called once by a program's main). Outputs are checked against the
// inputs: an output may not be, or contain, one of the run's inputs, and two outputs of one run
// may not be the same path.

#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace ramtk {

// Registry of temporary files and folders being written (thread-safe). Paths still registered
// when the process is interrupted are removed by the interrupt handler.
void RegisterTemporary(const std::filesystem::path& path);
void UnregisterTemporary(const std::filesystem::path& path);
// Removes every registered temporary (files and folders) and puts back every old result that was
// moved aside for a replacement not yet in place; returns how many temporaries existed.
int RemoveRegisteredTemporaries();

// Blocks SIGINT, SIGTERM and SIGHUP in the calling thread (and so in every thread it starts
// later) and starts a thread that waits for them: on a signal it removes the registered
// temporaries, writes one line to stderr and ends the process with 128 + the signal number. Call
// first thing in main, before any other thread exists. Idempotent.
void InstallInterruptCleanup(const std::string& program_name);

// InputError when `output` is one of `inputs` (the same path, or the same file under another name:
// a hard link, compared by device and inode), is a folder that contains one of them, or lies
// inside an input that is a folder. `field` names the output option in the error. Paths that do
// not exist yet are compared lexically after resolving the existing part
// (std::filesystem::weakly_canonical).
void CheckOutputAgainstInputs(const std::string& output, const std::vector<std::string>& inputs,
                              const std::string& field);
// InputError when two of the named outputs (option name, path) are the same path or one folder
// contains another output. Empty paths are skipped.
void CheckOutputsDistinct(const std::vector<std::pair<std::string, std::string>>& named_outputs);

// An exclusive lock on writing `target`: flock(2) on "<target>.lock" beside it, held from the
// constructor to the destructor, which removes the lock file. Two runs into one output cannot
// both go on: the second gets an InputError naming the target (and the holder's process id)
// instead of silently replacing or mixing the first one's result. A process that dies holding
// the lock releases it with its descriptors, so a lock file left behind never blocks a later run.
class OutputLock {
 public:
  // `field` names the option in errors ("--out"). The folder of `target` must exist.
  OutputLock(const std::string& target, const std::string& field);
  ~OutputLock();
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;

 private:
  std::filesystem::path path_;
  int fd_ = -1;
};

// A folder of outputs written as a unit. The constructor checks the target (an existing
// non-empty target needs `overwrite`; its parent must exist) and creates a sibling temporary
// folder "<target>.partial-<pid>" to write into; Commit() moves the old target aside, moves the
// temporary into place and only then removes the old one. An interruption between the two moves
// puts the old target back (RemoveRegisteredTemporaries), so at every point either the old or the
// new result is whole. Destroyed without Commit() (an error, a cancellation), it removes the
// temporary and leaves the old target untouched. The target is locked (OutputLock) for the
// object's lifetime: a second StagedFolder on it, in this or another process, is refused.
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
  std::unique_ptr<OutputLock> lock_;
  bool committed_ = false;
};

namespace detail {
// The points of StagedFolder::Commit between its steps, for tests that interrupt it there.
enum class CommitStep { kStart, kOldMovedAside, kNewInPlace, kOldRemoved };
// Called at each step of every Commit (empty: none). Not thread-safe; tests only.
void SetCommitStepHook(std::function<void(CommitStep)> hook);
}  // namespace detail

}  // namespace ramtk
