#include "app/serve/workspace.hpp"

#include <fmt/format.h>

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace asimov::serve {
namespace {

Error refused(const std::string& name, const core::FsError& e) {
  const char* message = e.kind == core::FsRefusal::not_found ? "*File not found*"
                        : e.kind == core::FsRefusal::outside ? "*Illegal file name*"
                        : e.kind == core::FsRefusal::bad_name ? "*Illegal file name*"
                                                              : "*Cannot access file*";
  return Error{message, fmt::format("{}: {}", name, e.why), name, 0, 0};
}

}  // namespace

Result<Workspace> Workspace::open(const std::filesystem::path& folder) {
  auto f = core::ConfinedFolder::open(folder);
  if (!f) return Error{"*File not found*", fmt::format("workspace {}: {}", folder.string(), f.error.why), folder.string(), 0, 0};
  return Workspace(std::move(*f.value));
}

Result<std::string> Workspace::read(const std::string& name) const {
  auto fd = folder_.open_read(name);
  if (!fd) return refused(name, fd.error);
  std::string bytes;
  char buf[65536];
  for (;;) {
    const ssize_t n = ::read(fd.value->get(), buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return Error{"*Cannot access file*", fmt::format("{}: {}", name, std::strerror(errno)), name, 0, 0};
    if (n == 0) break;
    if (bytes.size() + static_cast<std::size_t>(n) > kMaxFileBytes)
      return Error{"*Cannot access file*", fmt::format("{}: larger than {} bytes", name, kMaxFileBytes), name, 0, 0};
    bytes.append(buf, static_cast<std::size_t>(n));
  }
  return bytes;
}

Result<void> Workspace::write(const std::string& name, const std::string& bytes) const {
  auto file = folder_.create(name, /*replace=*/true);
  if (!file) return refused(name, file.error);
  if (auto w = core::write_all(file.value->fd(), bytes); !w) return refused(name, w.error);
  if (auto c = file.value->commit(); !c) return refused(name, c.error);
  return {};
}

std::vector<std::string> Workspace::list() const {
  std::vector<std::string> out;
  auto names = folder_.list(".", kMaxListed);
  if (!names) return out;
  for (const std::string& n : *names.value) {
    const auto ext = std::filesystem::path(n).extension().string();
    static const char* const kShown[] = {".v2", ".yaml", ".yml", ".dat", ".html", ".txt", ".session"};
    if (std::any_of(std::begin(kShown), std::end(kShown), [&](const char* e) { return ext == e; }) && folder_.is_file(n))
      out.push_back(n);
  }
  return out;
}

}  // namespace asimov::serve
