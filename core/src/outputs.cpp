#include "ramtk/core/outputs.h"

#include <csignal>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <set>
#include <thread>

#include <pthread.h>
#include <unistd.h>

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
  int removed = 0;
  for (const fs::path& p : Registry()) {
    std::error_code ec;
    if (fs::exists(p, ec)) ++removed;
    fs::remove_all(p, ec);
  }
  Registry().clear();
  return removed;
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
      const int removed = RemoveRegisteredTemporaries();
      std::fprintf(stderr, "%s: interrupted (%s); removed %d unfinished output%s, results left as before\n",
                   program_name.c_str(), strsignal(sig), removed, removed == 1 ? "" : "s");
      std::fflush(stderr);
      _exit(128 + sig);
    }).detach();
  });
}

void CheckOutputAgainstInputs(const std::string& output, const std::vector<std::string>& inputs,
                              const std::string& field) {
  if (output.empty()) return;
  const fs::path out = Resolve(output);
  for (const std::string& in : inputs) {
    if (in.empty()) continue;
    const fs::path i = Resolve(in);
    if (out == i) throw InputError({output, 0, field}, "is the input " + in + ": refusing to overwrite an input");
    if (Within(i, out)) {
      throw InputError({output, 0, field}, "contains the input " + in + ": replacing it would destroy an input");
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

StagedFolder::StagedFolder(const std::string& target, bool overwrite, const std::string& field) : field_(field) {
  if (target.empty()) throw InputError({"", 0, field}, "output folder is empty");
  target_ = fs::path(target).lexically_normal();
  if (target_.filename().empty()) target_ = target_.parent_path();
  std::error_code ec;
  if (fs::exists(target_, ec) && !(fs::is_directory(target_, ec) && fs::is_empty(target_, ec)) && !overwrite) {
    throw InputError({target, 0, field}, "output exists and is not an empty folder (pass --force to replace it)");
  }
  if (fs::exists(target_, ec) && !fs::is_directory(target_, ec)) {
    throw InputError({target, 0, field}, "output exists and is a file, not a folder");
  }
  const fs::path parent = target_.has_parent_path() ? target_.parent_path() : fs::path(".");
  if (!fs::is_directory(parent, ec)) throw InputError({target, 0, field}, "parent folder does not exist");
  tmp_ = fs::path(target_.string() + ".partial-" + std::to_string(::getpid()));
  fs::remove_all(tmp_, ec);
  RegisterTemporary(tmp_);
  if (!fs::create_directories(tmp_, ec)) {
    UnregisterTemporary(tmp_);
    throw InputError({tmp_.string(), 0, field}, "cannot create folder: " + ec.message());
  }
}

StagedFolder::~StagedFolder() {
  if (committed_) return;
  std::error_code ec;
  fs::remove_all(tmp_, ec);
  UnregisterTemporary(tmp_);
}

void StagedFolder::Commit() {
  std::error_code ec;
  fs::path old;
  if (fs::exists(target_, ec)) {
    // Move the old result aside first: until the rename below, the old result is intact.
    old = fs::path(target_.string() + ".old-" + std::to_string(::getpid()));
    fs::remove_all(old, ec);
    RegisterTemporary(old);
    fs::rename(target_, old, ec);
    if (ec) {
      UnregisterTemporary(old);
      throw InputError({target_.string(), 0, field_}, "cannot move the old output aside: " + ec.message());
    }
  }
  fs::rename(tmp_, target_, ec);
  if (ec) {
    std::error_code ec2;
    if (!old.empty()) fs::rename(old, target_, ec2);  // put the old result back
    if (!old.empty()) UnregisterTemporary(old);
    throw InputError({target_.string(), 0, field_}, "cannot move the outputs into place: " + ec.message());
  }
  UnregisterTemporary(tmp_);
  committed_ = true;
  if (!old.empty()) {
    // The old result is no longer needed; if an interruption comes now, the handler removes it.
    fs::remove_all(old, ec);
    UnregisterTemporary(old);
  }
}

}  // namespace ramtk
