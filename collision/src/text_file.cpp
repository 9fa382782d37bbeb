#include "asimov/collision/text_file.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <sys/stat.h>

namespace asimov::collision {

std::string read_file_bounded(const std::string& path, std::size_t max_bytes) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) throw FileReadError(fmt::format("cannot open the file ({})", std::strerror(errno)));
  if (S_ISDIR(st.st_mode)) throw FileReadError("is a directory, not a file");
  const auto too_large = [&] {
    return FileReadError(fmt::format("is larger than {} MiB, the limit for this kind of file", max_bytes >> 20));
  };
  if (S_ISREG(st.st_mode) && static_cast<std::size_t>(st.st_size) > max_bytes) throw too_large();
  const std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!f) throw FileReadError(fmt::format("cannot open the file ({})", std::strerror(errno)));
  // Read in chunks up to one byte past the limit: devices and pipes have no size to check first.
  std::string text;
  // A regular file's size is known: one buffer of it (growing by doubling held up to twice the
  // file while copying, 100 MB for a 1M-face STL).
  if (S_ISREG(st.st_mode)) text.reserve(static_cast<std::size_t>(st.st_size) + 1);
  char buf[1 << 16];
  for (;;) {
    const std::size_t n = std::fread(buf, 1, sizeof buf, f.get());
    if (n > 0) {
      if (text.size() + n > max_bytes) throw too_large();
      text.append(buf, n);
    }
    if (n < sizeof buf) {
      if (std::ferror(f.get())) throw FileReadError(fmt::format("cannot read the file ({})", std::strerror(errno)));
      break;
    }
  }
  return text;
}

}  // namespace asimov::collision
