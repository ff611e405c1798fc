#include "ramtk/core/file_io.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

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

std::string ReadTextFile(const std::string& path) {
  RequireRegularFile(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError({path, 0, ""}, "cannot open file");
  std::stringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw InputError({path, 0, ""}, "read failed");
  return ss.str();
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
