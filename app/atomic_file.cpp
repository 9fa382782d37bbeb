#include "app/atomic_file.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <fstream>

#include <unistd.h>

namespace asimov::app {

Result<void> write_file_atomically(const std::string& path, const std::string& text) {
  // The pid keeps concurrent writers (asimov test -j, two runs) off each other's temporary file.
  const std::string tmp = fmt::format("{}.tmp{}", path, ::getpid());
  std::error_code ec;
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) return Error{fmt::format("cannot write {}", tmp), {}, path, 0};
    out << text;
    out.flush();
    if (!out) {
      std::filesystem::remove(tmp, ec);
      return Error{fmt::format("error while writing {}", tmp), {}, path, 0};
    }
  }
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    Error e{fmt::format("cannot rename {} to {}: {}", tmp, path, ec.message()), {}, path, 0};
    std::filesystem::remove(tmp, ec);
    return e;
  }
  return {};
}

}  // namespace asimov::app
