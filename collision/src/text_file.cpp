#include "asimov/collision/text_file.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <sys/stat.h>

namespace asimov::collision {
namespace {
struct FileReadError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

std::string read_or_throw(const std::string& path, std::size_t max_bytes) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) throw FileReadError(fmt::format("cannot open the file ({})", std::strerror(errno)));
  if (S_ISDIR(st.st_mode)) throw FileReadError("is a directory, not a file");
  const auto too_large = [&] {
    const std::string limit = max_bytes >= (1u << 20) ? fmt::format("{} MiB", max_bytes >> 20) : fmt::format("{} bytes", max_bytes);
    return FileReadError(fmt::format("is larger than {}, the limit for this kind of file", limit));
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
}  // namespace

InputFile classify_input_file(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    if (errno == ENOENT || errno == ENOTDIR) return {true, ""};
    return {false, fmt::format("cannot open the file ({})", std::strerror(errno))};
  }
  if (S_ISREG(st.st_mode)) return {};
  const char* what = S_ISDIR(st.st_mode)                            ? "is a folder, not a file"
                     : S_ISFIFO(st.st_mode)                         ? "is a FIFO, not a regular file"
                     : S_ISCHR(st.st_mode) || S_ISBLK(st.st_mode)   ? "is a device, not a regular file"
                     : S_ISSOCK(st.st_mode)                         ? "is a socket, not a regular file"
                                                                    : "is not a regular file";
  return {false, what};
}

Result<std::string> read_file_bounded(const std::string& path, std::size_t max_bytes) {
  try {
    return read_or_throw(path, max_bytes);
  } catch (const FileReadError& e) {
    return Error{e.what(), "", path};
  }
}

std::string printable(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size();) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c == '\t' || (c >= 0x20 && c < 0x7f)) {
      out += static_cast<char>(c);
      ++i;
      continue;
    }
    // A UTF-8 sequence: its length from the lead byte, continuation bytes 10xxxxxx, no overlong
    // form, no surrogate, nothing above U+10FFFF, and no C1 control (U+0080..U+009F).
    const std::size_t n = c >= 0xc2 && c <= 0xdf ? 2 : c >= 0xe0 && c <= 0xef ? 3 : c >= 0xf0 && c <= 0xf4 ? 4 : 0;
    bool ok = n > 0 && i + n <= text.size();
    for (std::size_t k = 1; ok && k < n; ++k) ok = (static_cast<unsigned char>(text[i + k]) & 0xc0) == 0x80;
    if (ok) {
      const auto b1 = static_cast<unsigned char>(text[i + 1]);
      if ((c == 0xe0 && b1 < 0xa0) || (c == 0xed && b1 >= 0xa0) || (c == 0xf0 && b1 < 0x90) || (c == 0xf4 && b1 >= 0x90) ||
          (c == 0xc2 && b1 < 0xa0))
        ok = false;
    }
    if (ok) {
      out.append(text.substr(i, n));
      i += n;
    } else {
      out += '?';
      ++i;
    }
  }
  return out;
}

}  // namespace asimov::collision
