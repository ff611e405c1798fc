#include "ramtk/core/outputs.h"

#include <fcntl.h>
#include <pthread.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <map>
#include <mutex>
#include <set>
#include <thread>

#include "ramtk/core/error.h"

namespace fs = std::filesystem;

namespace ramtk {
namespace {

std::mutex& RegistryMutex() {
  static std::mutex m;
  return m;
}
std::set<fs::path>& Registry() {
  static std::set<fs::path> r;
  return r;
}
// Old results moved aside whose replacement is not in place yet: aside -> target. Changed only
// under RegistryMutex together with the rename it describes, so a cleanup sees each move either
// done or not.
std::map<fs::path, fs::path>& Restores() {
  static std::map<fs::path, fs::path> r;
  return r;
}

std::function<void(detail::CommitStep)>& CommitHook() {
  static std::function<void(detail::CommitStep)> hook;
  return hook;
}
void AtStep(detail::CommitStep step) {
  if (CommitHook()) CommitHook()(step);
}

// Puts back every old result moved aside, then removes the temporaries. The caller holds
// RegistryMutex.
int CleanUpLocked() {
  for (const auto& [aside, target] : Restores()) {
    std::error_code ec;
    // Never remove an old result that could not be put back: it stays as <target>.old-<pid>.
    if (!fs::exists(target, ec)) fs::rename(aside, target, ec);
  }
  Restores().clear();
  int removed = 0;
  for (const fs::path& p : Registry()) {
    std::error_code ec;
    if (fs::exists(fs::symlink_status(p, ec))) ++removed;
    fs::remove_all(p, ec);
  }
  Registry().clear();
  return removed;
}

// The existing part resolved, the rest appended lexically; absolute.
fs::path Resolve(const std::string& p) {
  std::error_code ec;
  fs::path r = fs::weakly_canonical(fs::absolute(fs::path(p), ec), ec);
  if (ec) r = fs::absolute(fs::path(p)).lexically_normal();
  // "DIR/" and "DIR" are the same folder.
  if (r.filename().empty()) r = r.parent_path();
  return r;
}

// True when `inner` is `outer` or lies below it.
bool Within(const fs::path& inner, const fs::path& outer) {
  auto o = outer.begin(), i = inner.begin();
  for (; o != outer.end(); ++o, ++i) {
    if (i == inner.end() || *o != *i) return false;
  }
  return true;
}

}  // namespace

void RegisterTemporary(const fs::path& path) {
  std::lock_guard<std::mutex> lock(RegistryMutex());
  Registry().insert(fs::absolute(path));
}

void UnregisterTemporary(const fs::path& path) {
  std::lock_guard<std::mutex> lock(RegistryMutex());
  Registry().erase(fs::absolute(path));
}

int RemoveRegisteredTemporaries() {
  std::lock_guard<std::mutex> lock(RegistryMutex());
  return CleanUpLocked();
}

void InstallInterruptCleanup(const std::string& program_name) {
  static std::once_flag once;
  std::call_once(once, [program_name] {
    sigset_t set;
    sigemptyset(&set);
    sigaddset(&set, SIGINT);
    sigaddset(&set, SIGTERM);
    sigaddset(&set, SIGHUP);
    pthread_sigmask(SIG_BLOCK, &set, nullptr);
    std::thread([set, program_name]() mutable {
      int sig = 0;
      while (sigwait(&set, &sig) != 0) {
      }
      // The registry stays locked until _exit: no other thread may move an output after the
      // cleanup has restored the old one.
      RegistryMutex().lock();
      const int removed = CleanUpLocked();
      std::fprintf(stderr, "%s: interrupted (%s); removed %d unfinished output%s, results left as before\n",
                   program_name.c_str(), strsignal(sig), removed, removed == 1 ? "" : "s");
      std::fflush(stderr);
      _exit(128 + sig);
    }).detach();
  });
}

namespace {
// True when both paths exist and are one file under two names (a hard link; symbolic links are
// followed).
bool SameFile(const fs::path& a, const fs::path& b) {
  struct stat sa = {};
  struct stat sb = {};
  return ::stat(a.c_str(), &sa) == 0 && ::stat(b.c_str(), &sb) == 0 && sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}
}  // namespace

void CheckOutputAgainstInputs(const std::string& output, const std::vector<std::string>& inputs,
                              const std::string& field) {
  if (output.empty()) return;
  const fs::path out = Resolve(output);
  for (const std::string& in : inputs) {
    if (in.empty()) continue;
    const fs::path i = Resolve(in);
    if (out == i || SameFile(out, i))
      throw InputError({output, 0, field}, "is the input " + in + ": refusing to overwrite an input");
    if (Within(i, out)) {
      throw InputError({output, 0, field}, "contains the input " + in + ": replacing it would destroy an input");
    }
    std::error_code ec;
    if (Within(out, i) && fs::is_directory(i, ec)) {
      throw InputError({output, 0, field},
                       "lies inside the input folder " + in + ": an output may not change an input");
    }
  }
}

void CheckOutputsDistinct(const std::vector<std::pair<std::string, std::string>>& named_outputs) {
  for (std::size_t a = 0; a < named_outputs.size(); ++a) {
    if (named_outputs[a].second.empty()) continue;
    const fs::path pa = Resolve(named_outputs[a].second);
    for (std::size_t b = a + 1; b < named_outputs.size(); ++b) {
      if (named_outputs[b].second.empty()) continue;
      const fs::path pb = Resolve(named_outputs[b].second);
      if (pa == pb || Within(pa, pb) || Within(pb, pa)) {
        throw InputError({named_outputs[b].second, 0, named_outputs[b].first},
                         "same path as (or inside) " + named_outputs[a].first + " " + named_outputs[a].second +
                             ": each output needs its own path");
      }
    }
  }
}

namespace {

std::string HolderOf(const fs::path& lock_file) {
  std::error_code ec;
  if (!fs::is_regular_file(lock_file, ec)) return "";
  std::FILE* f = std::fopen(lock_file.c_str(), "r");
  if (!f) return "";
  char buf[32] = {};
  const std::size_t n = std::fread(buf, 1, sizeof buf - 1, f);
  std::fclose(f);
  std::string pid(buf, n);
  while (!pid.empty() && (pid.back() == '\n' || pid.back() == ' ')) pid.pop_back();
  return pid.empty() ? "" : " by process " + pid;
}

// True when the descriptor still refers to the file at `path` (its previous holder may have
// removed the lock file between our open and our flock).
bool StillLinked(int fd, const fs::path& path) {
  struct stat a = {};
  struct stat b = {};
  return ::fstat(fd, &a) == 0 && ::stat(path.c_str(), &b) == 0 && a.st_dev == b.st_dev && a.st_ino == b.st_ino;
}

}  // namespace

OutputLock::OutputLock(const std::string& target, const std::string& field) {
  fs::path t = fs::path(target).lexically_normal();
  if (t.filename().empty()) t = t.parent_path();
  path_ = fs::path(t.string() + ".lock");
  // Created and registered under the registry's lock: an interruption's cleanup (which keeps that
  // lock until the process exits) finds the lock file either not made yet or registered.
  std::lock_guard<std::mutex> registry(RegistryMutex());
  for (int attempt = 0; attempt < 100; ++attempt) {
    fd_ = ::open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd_ < 0)
      throw InputError({target, 0, field},
                       "cannot create the lock file " + path_.string() + ": " + std::strerror(errno));
    if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
      const int err = errno;
      ::close(fd_);
      fd_ = -1;
      if (err == EWOULDBLOCK)
        throw InputError({target, 0, field}, "another run is writing this output (lock " + path_.string() + " held" +
                                                 HolderOf(path_) + "): wait for it to finish or choose another path");
      throw InputError({target, 0, field}, "cannot lock " + path_.string() + ": " + std::strerror(err));
    }
    if (StillLinked(fd_, path_)) break;
    ::close(fd_);
    fd_ = -1;
  }
  if (fd_ < 0) throw InputError({target, 0, field}, "cannot lock " + path_.string() + ": it keeps being replaced");
  Registry().insert(fs::absolute(path_));
  const std::string pid = std::to_string(::getpid()) + "\n";
  if (::ftruncate(fd_, 0) != 0 || ::write(fd_, pid.data(), pid.size()) < 0) {
    // The process id is only a hint in the error of a second run; the lock holds without it.
  }
}

OutputLock::~OutputLock() {
  // Removed before the descriptor is closed, so a run waiting on this file re-opens a new one.
  std::error_code ec;
  fs::remove(path_, ec);
  UnregisterTemporary(path_);
  ::close(fd_);
}

StagedFolder::StagedFolder(const std::string& target, bool overwrite, const std::string& field) : field_(field) {
  if (target.empty()) throw InputError({"", 0, field}, "output folder is empty");
  target_ = fs::path(target).lexically_normal();
  if (target_.filename().empty()) target_ = target_.parent_path();
  std::error_code ec;
  const fs::path parent = target_.has_parent_path() ? target_.parent_path() : fs::path(".");
  if (!fs::is_directory(parent, ec)) throw InputError({target, 0, field}, "parent folder does not exist");
  // Locked before the checks below, so that two runs cannot both find the target free.
  lock_ = std::make_unique<OutputLock>(target_.string(), field);
  if (fs::exists(target_, ec) && !(fs::is_directory(target_, ec) && fs::is_empty(target_, ec)) && !overwrite) {
    throw InputError({target, 0, field}, "output exists and is not an empty folder (pass --force to replace it)");
  }
  if (fs::exists(target_, ec) && !fs::is_directory(target_, ec)) {
    throw InputError({target, 0, field}, "output exists and is a file, not a folder");
  }
  tmp_ = fs::path(target_.string() + ".partial-" + std::to_string(::getpid()));
  fs::remove_all(tmp_, ec);
  // Made and registered in one step under the registry's lock: an interruption's cleanup (which
  // keeps that lock until the process exits) finds the folder either not made yet or registered,
  // never made after it ran.
  std::lock_guard<std::mutex> registry(RegistryMutex());
  if (!fs::create_directories(tmp_, ec))
    throw InputError({tmp_.string(), 0, field}, "cannot create folder: " + ec.message());
  Registry().insert(fs::absolute(tmp_));
}

StagedFolder::~StagedFolder() {
  if (committed_) return;
  std::error_code ec;
  fs::remove_all(tmp_, ec);
  UnregisterTemporary(tmp_);
}

// Each rename happens under RegistryMutex together with the registry change that describes it,
// so an interruption's cleanup finds either the old result in place, or the old result aside
// (and puts it back), or the new one in place (and removes the old one).
void StagedFolder::Commit() {
  AtStep(detail::CommitStep::kStart);
  std::error_code ec;
  fs::path old;
  if (fs::exists(target_, ec)) {
    old = fs::path(target_.string() + ".old-" + std::to_string(::getpid()));
    fs::remove_all(old, ec);
    {
      std::lock_guard<std::mutex> lock(RegistryMutex());
      fs::rename(target_, old, ec);
      if (!ec) Restores()[fs::absolute(old)] = fs::absolute(target_);
    }
    if (ec) throw InputError({target_.string(), 0, field_}, "cannot move the old output aside: " + ec.message());
    AtStep(detail::CommitStep::kOldMovedAside);
  }
  {
    std::lock_guard<std::mutex> lock(RegistryMutex());
    fs::rename(tmp_, target_, ec);
    if (ec) {
      std::error_code ec2;
      if (!old.empty()) fs::rename(old, target_, ec2);  // put the old result back
    }
    if (!old.empty()) Restores().erase(fs::absolute(old));
    if (!ec) {
      Registry().erase(fs::absolute(tmp_));
      if (!old.empty()) Registry().insert(fs::absolute(old));  // no longer needed: removed if interrupted
    }
  }
  if (ec) throw InputError({target_.string(), 0, field_}, "cannot move the outputs into place: " + ec.message());
  committed_ = true;
  AtStep(detail::CommitStep::kNewInPlace);
  if (!old.empty()) {
    fs::remove_all(old, ec);
    UnregisterTemporary(old);
  }
  AtStep(detail::CommitStep::kOldRemoved);
}

namespace detail {
void SetCommitStepHook(std::function<void(CommitStep)> hook) { CommitHook() = std::move(hook); }
}  // namespace detail

}  // namespace ramtk
