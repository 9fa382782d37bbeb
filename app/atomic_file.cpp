#include "app/atomic_file.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <fstream>

#include <unistd.h>

namespace asimov::app {

bool write_file_atomically(const std::string& path, const std::string& text, std::string& why) {
  // The pid keeps concurrent writers (asimov test -j, two runs) off each other's temporary file.
  const std::string tmp = fmt::format("{}.tmp{}", path, ::getpid());
  std::error_code ec;
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) {
      why = fmt::format("cannot write {}", tmp);
      return false;
    }
    out << text;
    out.flush();
    if (!out) {
      why = fmt::format("error while writing {}", tmp);
      std::filesystem::remove(tmp, ec);
      return false;
    }
  }
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    why = fmt::format("cannot rename {} to {}: {}", tmp, path, ec.message());
    std::filesystem::remove(tmp, ec);
    return false;
  }
  return true;
}

}  // namespace asimov::app
