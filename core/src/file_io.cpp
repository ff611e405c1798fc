#include "ramtk/core/file_io.h"

#include <cstdio>
#include <fstream>
#include <sstream>

#include <unistd.h>

#include "ramtk/core/error.h"

namespace ramtk {

std::string ReadTextFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError({path, 0, ""}, "cannot open file");
  std::stringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw InputError({path, 0, ""}, "read failed");
  return ss.str();
}

void WriteFileAtomically(const std::string& path, const std::string& contents) {
  const std::string tmp = path + ".tmp" + std::to_string(::getpid());
  {
    std::ofstream out(tmp, std::ios::binary);
    if (!out) throw InputError({path, 0, ""}, "cannot write file");
    out << contents;
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

}  // namespace ramtk
