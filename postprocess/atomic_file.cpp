#include "atomic_file.h"

#include <fmt/format.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>

#include "freestand/input_error.h"

namespace freestand {

void publish_file(const std::string& temporary, const std::string& path) {
  if (std::rename(temporary.c_str(), path.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    std::remove(temporary.c_str());
    throw InputError(fmt::format("{}: cannot rename {} into place ({})", path, temporary, reason));
  }
}

void write_file_atomically(const std::string& path, const std::string& content) {
  const std::string part = path + ".part";
  {
    std::ofstream out(part, std::ios::binary | std::ios::trunc);
    if (!out) throw InputError(fmt::format("{}: cannot create file ({})", part, std::strerror(errno)));
    out << content;
    out.close();
    if (!out) {
      std::remove(part.c_str());
      throw InputError(fmt::format("{}: write failed", part));
    }
  }
  publish_file(part, path);
}

}  // namespace freestand
