#include "asimov/core/output_file.hpp"

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace asimov::core {
namespace {

namespace fs = std::filesystem;

std::string reason(int err) { return std::strerror(err); }

const char* kind_of(mode_t mode) {
  if (S_ISDIR(mode)) return "is a folder, not a file";
  if (S_ISFIFO(mode)) return "is a FIFO, not a regular file";
  if (S_ISCHR(mode) || S_ISBLK(mode)) return "is a device, not a regular file";
  if (S_ISSOCK(mode)) return "is a socket, not a regular file";
  return "is not a regular file";
}

Error failure(const std::string& path, const std::string& what) { return Error{path + ": " + what, {}, path, 0}; }

}  // namespace

std::string output_target(const std::string& path) {
  // Follow the links one by one (relative ones from their own folder), at most 40 as the kernel.
  fs::path p(path);
  for (int hops = 0; hops < 40; ++hops) {
    std::error_code ec;
    if (!fs::is_symlink(fs::symlink_status(p, ec))) return p.string();
    const fs::path to = fs::read_symlink(p, ec);
    if (ec) return p.string();
    p = to.is_absolute() ? to : p.parent_path() / to;
  }
  return p.string();
}

Result<void> check_output_path(const std::string& path) {
  if (path.empty()) return failure(path, "no file name");
  const std::string target = output_target(path);
  struct stat st {};
  if (::lstat(target.c_str(), &st) == 0) {
    if (S_ISLNK(st.st_mode)) return failure(path, "too many levels of symbolic links");
    if (!S_ISREG(st.st_mode))
      return failure(path, std::string(kind_of(st.st_mode)) + (target != path ? " (the link leads to " + target + ")" : "") +
                               "; an output replaces only a regular file");
    return {};
  }
  if (errno != ENOENT) return failure(target, reason(errno));
  const fs::path folder = fs::path(target).parent_path();
  struct stat dir {};
  if (!folder.empty() && (::stat(folder.c_str(), &dir) != 0 || !S_ISDIR(dir.st_mode)))
    return failure(target, "no folder " + folder.string());
  return {};
}

Result<void> write_output_file(const std::string& path, std::string_view text) {
  if (auto ok = check_output_path(path); !ok) return ok;
  const std::string target = output_target(path);
  const fs::path folder = fs::path(target).parent_path();
  // Beside the target (a rename never crosses file systems), a name no other writer uses: the
  // pid and a counter (asimov test -j, two runs, two outputs of one run).
  static std::atomic<unsigned> counter{0};
  const std::string name = fs::path(target).filename().string();
  const std::string temp = (folder / ("." + name + ".tmp" + std::to_string(::getpid()) + "-" +
                                      std::to_string(counter.fetch_add(1)))).string();
  struct stat old {};
  const bool replacing = ::stat(target.c_str(), &old) == 0;
  const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC | O_NOCTTY, 0644);
  if (fd < 0) return failure(target, "cannot write beside it: " + reason(errno));
  const auto fail = [&](const char* what, int err) {
    ::close(fd);
    ::unlink(temp.c_str());
    return failure(target, std::string(what) + ": " + reason(err));
  };
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return fail("cannot write", n < 0 ? errno : ENOSPC);
    done += static_cast<std::size_t>(n);
  }
  if (replacing) (void)::fchmod(fd, old.st_mode & 07777);  // keep the old file's permissions
  if (::fsync(fd) != 0 && errno != EINVAL) return fail("cannot write", errno);
  if (::close(fd) != 0) {
    const int err = errno;
    ::unlink(temp.c_str());
    return failure(target, "cannot write: " + reason(err));
  }
  // Checked again just before the rename: a FIFO or device put there meanwhile is not replaced.
  if (auto ok = check_output_path(target); !ok) {
    ::unlink(temp.c_str());
    return ok;
  }
  if (::rename(temp.c_str(), target.c_str()) != 0) {
    const int err = errno;
    ::unlink(temp.c_str());
    return failure(target, "cannot replace it: " + reason(err));
  }
  if (const int dir = ::open(folder.empty() ? "." : folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC); dir >= 0) {
    ::fsync(dir);  // the rename itself reaches the disk
    ::close(dir);
  }
  return {};
}

bool same_file(const std::string& a, const std::string& b) {
  if (a.empty() || b.empty()) return false;
  struct stat sa {}, sb {};
  const bool ea = ::stat(a.c_str(), &sa) == 0, eb = ::stat(b.c_str(), &sb) == 0;
  if (ea && eb) return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
  if (ea != eb) return false;
  std::error_code ec1, ec2;
  const fs::path ca = fs::weakly_canonical(fs::absolute(output_target(a)), ec1);
  const fs::path cb = fs::weakly_canonical(fs::absolute(output_target(b)), ec2);
  return !ec1 && !ec2 && ca == cb;
}

Result<void> check_outputs_apart(const std::vector<NamedPath>& inputs, const std::vector<NamedPath>& outputs) {
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    const NamedPath& o = outputs[i];
    if (o.path.empty() || o.path == "-") continue;
    for (const NamedPath& in : inputs)
      if (same_file(o.path, in.path))
        return failure(o.path, "is " + in.role + " (an input of this run); " + o.role + " would overwrite it");
    for (std::size_t k = 0; k < i; ++k)
      if (outputs[k].path != "-" && same_file(o.path, outputs[k].path))
        return failure(o.path, "is given to both " + outputs[k].role + " and " + o.role + "; each output needs its own file");
  }
  return {};
}

}  // namespace asimov::core
