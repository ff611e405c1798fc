#include "ramtk/core/file_io.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <sstream>
#include <thread>
#include <vector>

#include "ramtk/core/error.h"
#include "ramtk/core/outputs.h"

namespace ramtk {

void RequireRegularFile(const std::string& path) {
  struct stat st = {};
  if (::stat(path.c_str(), &st) != 0) {
    const int err = errno;
    throw InputError({path, 0, ""}, std::string("cannot open file: ") + std::strerror(err));
  }
  if (S_ISREG(st.st_mode)) return;
  // A folder opens as a stream on Linux and then reads as empty; a FIFO blocks until a writer
  // comes; a device such as /dev/zero never ends.
  if (S_ISDIR(st.st_mode)) throw InputError({path, 0, ""}, "is a folder, not a file");
  const char* what = S_ISFIFO(st.st_mode)   ? "is a FIFO (named pipe)"
                     : S_ISCHR(st.st_mode)  ? "is a character device"
                     : S_ISBLK(st.st_mode)  ? "is a block device"
                     : S_ISSOCK(st.st_mode) ? "is a socket"
                                            : "is a special file";
  throw InputError({path, 0, ""},
                   std::string(what) + ", not a regular file: refusing to read it (it could block or never end)");
}

namespace {
std::atomic<double> g_read_deadline_s{0.0};    // <= 0: from the environment or the default
constexpr double kLongestReadDeadlineS = 1e7;  // beyond this a steady_clock deadline could overflow
}  // namespace

double ReadDeadlineSeconds() {
  const double set = g_read_deadline_s.load();
  if (set > 0) return set;
  if (const char* env = std::getenv("RAMTK_READ_DEADLINE_S")) {
    char* end = nullptr;
    const double v = std::strtod(env, &end);
    if (end != env && *end == '\0' && std::isfinite(v) && v > 0) return std::min(v, kLongestReadDeadlineS);
  }
  return kDefaultReadDeadlineS;
}

void SetReadDeadline(double seconds) {
  g_read_deadline_s = seconds > 0 && std::isfinite(seconds) ? std::min(seconds, kLongestReadDeadlineS) : 0.0;
}

std::string ReadToEndWithDeadline(int fd, const std::string& path, double deadline_s) {
  struct Shared {
    std::mutex mutex;
    std::condition_variable finished;
    std::string data;
    bool done = false;
    int error = 0;
    std::atomic<bool> cancel{false};
  };
  auto shared = std::make_shared<Shared>();
  std::thread reader([shared, fd] {
    std::string data;
    std::vector<char> chunk(1 << 20);
    int error = 0;
    while (!shared->cancel.load()) {
      const ssize_t n = ::read(fd, chunk.data(), chunk.size());
      if (n > 0) {
        data.append(chunk.data(), static_cast<std::size_t>(n));
      } else if (n == 0) {
        break;
      } else if (errno != EINTR) {
        error = errno;
        break;
      }
    }
    ::close(fd);
    std::lock_guard<std::mutex> lock(shared->mutex);
    shared->data = std::move(data);
    shared->error = error;
    shared->done = true;
    shared->finished.notify_all();
  });
  std::unique_lock<std::mutex> lock(shared->mutex);
  const bool done =
      shared->finished.wait_for(lock, std::chrono::duration<double>(deadline_s), [&] { return shared->done; });
  if (!done) {
    shared->cancel = true;
    lock.unlock();
    reader.detach();  // owns `shared` and `fd`; ends at its next chunk
    char limit[32];
    std::snprintf(limit, sizeof limit, "%g", deadline_s);
    throw InputError({path, 0, ""}, std::string("reading did not finish within ") + limit +
                                        " s (a stalled network file system, or a file that never ends?); "
                                        "RAMTK_READ_DEADLINE_S sets this limit");
  }
  lock.unlock();
  reader.join();
  if (shared->error != 0) throw InputError({path, 0, ""}, std::string("read failed: ") + std::strerror(shared->error));
  return std::move(shared->data);
}

std::string ReadTextFile(const std::string& path) {
  RequireRegularFile(path);
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    const int err = errno;
    throw InputError({path, 0, ""}, std::string("cannot open file: ") + std::strerror(err));
  }
  return ReadToEndWithDeadline(fd, path, ReadDeadlineSeconds());
}

void WriteFileAtomically(const std::string& path, const std::string& contents) {
  WriteFileAtomically(path, [&contents](std::ostream& out) { out << contents; });
}

void WriteFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& write) {
  const std::string tmp = path + ".tmp" + std::to_string(::getpid());
  RegisterTemporary(tmp);
  struct Unregister {
    const std::string& p;
    ~Unregister() { UnregisterTemporary(p); }
  } unregister{tmp};
  {
    std::ofstream out(tmp, std::ios::binary);
    if (!out) throw InputError({path, 0, ""}, "cannot write file");
    try {
      write(out);
    } catch (...) {
      out.close();
      std::remove(tmp.c_str());
      throw;
    }
    out.flush();
    if (!out) {
      out.close();
      std::remove(tmp.c_str());
      throw InputError({path, 0, ""}, "write failed");
    }
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    std::remove(tmp.c_str());
    throw InputError({path, 0, ""}, "cannot move the written file into place");
  }
}

void WriteFilesAtomically(const std::vector<std::pair<std::string, std::string>>& path_and_contents) {
  std::vector<std::pair<std::string, std::string>> outputs;
  for (const auto& [path, contents] : path_and_contents) outputs.emplace_back(path, path);
  CheckOutputsDistinct(outputs);
  std::vector<std::string> temporaries;
  auto remove_all = [&temporaries] {
    for (const std::string& t : temporaries) {
      std::remove(t.c_str());
      UnregisterTemporary(t);
    }
  };
  try {
    for (const auto& [path, contents] : path_and_contents) {
      const std::string tmp = path + ".tmp" + std::to_string(::getpid());
      RegisterTemporary(tmp);
      temporaries.push_back(tmp);
      std::ofstream out(tmp, std::ios::binary);
      if (!out) throw InputError({path, 0, ""}, "cannot write file");
      out << contents;
      out.flush();
      if (!out) throw InputError({path, 0, ""}, "write failed");
    }
  } catch (...) {
    remove_all();
    throw;
  }
  for (std::size_t i = 0; i < path_and_contents.size(); ++i) {
    if (std::rename(temporaries[i].c_str(), path_and_contents[i].first.c_str()) != 0) {
      remove_all();
      throw InputError({path_and_contents[i].first, 0, ""}, "cannot move the written file into place");
    }
    UnregisterTemporary(temporaries[i]);
  }
}

}  // namespace ramtk
