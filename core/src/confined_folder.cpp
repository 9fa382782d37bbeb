#include "asimov/core/confined_folder.hpp"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <deque>
#include <thread>

#include <dirent.h>
#include <fcntl.h>
#include <linux/openat2.h>  // struct open_how, RESOLVE_*
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>

namespace asimov::core {

namespace {

constexpr std::size_t kMaxName = 4096;  // PATH_MAX
constexpr int kMaxLinks = 40;          // as the kernel's own ELOOP limit

FsError error_of(int err) {
  switch (err) {
    case ENOENT: case ENOTDIR: return {FsRefusal::not_found, "does not exist"};
    case EXDEV: return {FsRefusal::outside, "leaves the folder"};
    case EEXIST: return {FsRefusal::exists, "exists already"};
    case EISDIR: return {FsRefusal::is_folder, "is a folder, not a file"};
    case ENXIO: return {FsRefusal::not_regular, "is a FIFO or socket, not a regular file"};
    case ELOOP: return {FsRefusal::bad_name, "has too many links"};
    case ENAMETOOLONG: return {FsRefusal::bad_name, "is too long"};
    default: return {FsRefusal::io, std::strerror(err)};
  }
}

FsError kind_error(mode_t mode) {
  if (S_ISDIR(mode)) return {FsRefusal::is_folder, "is a folder, not a file"};
  if (S_ISFIFO(mode)) return {FsRefusal::not_regular, "is a FIFO, not a regular file"};
  if (S_ISSOCK(mode)) return {FsRefusal::not_regular, "is a socket, not a regular file"};
  if (S_ISCHR(mode) || S_ISBLK(mode)) return {FsRefusal::not_regular, "is a device, not a regular file"};
  return {FsRefusal::not_regular, "is not a regular file"};
}

// The relative path's own faults, before the kernel sees it.
std::optional<FsError> name_fault(std::string_view name) {
  if (name.empty()) return FsError{FsRefusal::bad_name, "is an empty name"};
  if (name.size() > kMaxName) return FsError{FsRefusal::bad_name, "is too long"};
  if (name.find('\0') != std::string_view::npos) return FsError{FsRefusal::bad_name, "holds a NUL byte"};
  if (name.front() == '/') return FsError{FsRefusal::outside, "is an absolute path"};
  return std::nullopt;
}

std::vector<std::string> components(std::string_view path) {
  std::vector<std::string> out;
  std::size_t i = 0;
  while (i <= path.size()) {
    const std::size_t j = std::min(path.find('/', i), path.size());
    if (j > i) out.emplace_back(path.substr(i, j - i));
    i = j + 1;
  }
  return out;
}

// openat2 through syscall(): glibc 2.36 has no wrapper. -1 and errno as the kernel sets them.
int openat2_beneath(int dir, const char* path, int flags, unsigned mode) {
  open_how how{};
  how.flags = static_cast<std::uint64_t>(flags);
  how.mode = (flags & (O_CREAT | O_TMPFILE)) ? mode : 0;
  how.resolve = RESOLVE_BENEATH | RESOLVE_NO_MAGICLINKS;
  return static_cast<int>(::syscall(SYS_openat2, dir, path, &how, sizeof how));
}

// The kernel refuses openat2 itself (not the path): use the walk from now on.
bool kernel_lacks_openat2(int err) { return err == ENOSYS || err == EPERM || err == E2BIG || err == EINVAL; }

// The walk: RESOLVE_BENEATH's rule done by hand. Each component is looked at without following
// it (fstatat AT_SYMLINK_NOFOLLOW); a link is read and its (relative) text put in its place, an
// absolute one is refused; `..` pops the folders walked and fails past the first; folders are
// opened O_NOFOLLOW, so a component swapped for a link in between fails instead of being followed.
int walk_beneath(int root, std::string_view path, int flags, unsigned mode) {
  std::deque<std::string> todo;
  for (auto& c : components(path)) todo.push_back(std::move(c));
  std::vector<UniqueFd> folders;  // folders.back(): where the walk is; empty: at the root
  auto here = [&] { return folders.empty() ? root : folders.back().get(); };
  int links = 0;
  while (!todo.empty()) {
    const std::string c = std::move(todo.front());
    todo.pop_front();
    if (c == ".") continue;
    if (c == "..") {
      if (folders.empty()) {
        errno = EXDEV;
        return -1;
      }
      folders.pop_back();
      continue;
    }
    const bool last = todo.empty();
    struct stat st {};
    if (::fstatat(here(), c.c_str(), &st, AT_SYMLINK_NOFOLLOW) != 0) {
      if (errno == ENOENT && last && (flags & O_CREAT)) return ::openat(here(), c.c_str(), flags | O_NOFOLLOW, mode);
      return -1;
    }
    if (S_ISLNK(st.st_mode)) {
      if (++links > kMaxLinks) {
        errno = ELOOP;
        return -1;
      }
      std::string target(kMaxName + 1, '\0');
      const ssize_t n = ::readlinkat(here(), c.c_str(), target.data(), target.size());
      if (n < 0) return -1;
      if (static_cast<std::size_t>(n) > kMaxName) {
        errno = ENAMETOOLONG;
        return -1;
      }
      target.resize(static_cast<std::size_t>(n));
      if (target.empty() || target.front() == '/') {
        errno = EXDEV;
        return -1;
      }
      auto parts = components(target);
      todo.insert(todo.begin(), parts.begin(), parts.end());
      if (parts.empty()) todo.push_front(".");
      continue;
    }
    if (last) return ::openat(here(), c.c_str(), (flags & ~O_CREAT) | O_NOFOLLOW, mode);
    const int fd = ::openat(here(), c.c_str(), O_PATH | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    if (fd < 0) return -1;
    folders.emplace_back(fd);
  }
  return ::openat(here(), ".", flags & ~O_CREAT, mode);  // the path names a folder ("a/..", ".")
}

}  // namespace

UniqueFd& UniqueFd::operator=(UniqueFd&& o) noexcept {
  if (this != &o) {
    reset();
    fd_ = std::exchange(o.fd_, -1);
  }
  return *this;
}
UniqueFd::~UniqueFd() { reset(); }
void UniqueFd::reset() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

FsResult<ConfinedFolder> ConfinedFolder::open(const std::filesystem::path& root, Resolver preferred) {
  const int fd = ::open(root.c_str(), O_PATH | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return error_of(errno);
  std::error_code ec;
  std::filesystem::path shown = std::filesystem::absolute(root, ec);
  if (ec) shown = root;
  return ConfinedFolder(UniqueFd(fd), shown, preferred);
}

FsResult<UniqueFd> ConfinedFolder::resolve(std::string_view name, int flags, unsigned mode) const {
  if (auto fault = name_fault(name)) return *fault;
  const std::string path(name);
  flags |= O_CLOEXEC | O_NOCTTY;
  if (resolver_ == Resolver::kernel) {
    for (int attempt = 0; attempt < 8; ++attempt) {
      const int fd = openat2_beneath(fd_.get(), path.c_str(), flags, mode);
      if (fd >= 0) return UniqueFd(fd);
      if (errno == EAGAIN || errno == EINTR) continue;  // a rename raced a `..`: the kernel asks again
      if (kernel_lacks_openat2(errno)) break;
      return error_of(errno);
    }
    // EINVAL is also what a kernel says for flags it does not know; the walk decides then.
    resolver_ = Resolver::walk;
  }
  const int fd = walk_beneath(fd_.get(), path, flags, mode);
  if (fd < 0) return error_of(errno);
  return UniqueFd(fd);
}

// Looked at through O_PATH first (opening a device or FIFO itself may act or block), then
// opened for real and checked to be the same file.
FsResult<UniqueFd> ConfinedFolder::open_regular(std::string_view name, int flags) const {
  auto probe = resolve(name, O_PATH);
  if (!probe) return probe.error;
  struct stat first {};
  if (::fstat(probe.value->get(), &first) != 0) return error_of(errno);
  if (!S_ISREG(first.st_mode)) return kind_error(first.st_mode);
  auto fd = resolve(name, flags | O_NONBLOCK);
  if (!fd) return fd.error;
  struct stat second {};
  if (::fstat(fd.value->get(), &second) != 0) return error_of(errno);
  if (second.st_dev != first.st_dev || second.st_ino != first.st_ino || !S_ISREG(second.st_mode))
    return FsError{FsRefusal::io, "changed while it was opened"};
  const int fl = ::fcntl(fd.value->get(), F_GETFL);
  if (fl >= 0) ::fcntl(fd.value->get(), F_SETFL, fl & ~O_NONBLOCK);
  return fd;
}

FsResult<std::pair<UniqueFd, std::string>> ConfinedFolder::parent_of(std::string_view name) const {
  if (auto fault = name_fault(name)) return *fault;
  while (name.size() > 1 && name.back() == '/' && name[name.size() - 2] == '/') name.remove_suffix(1);
  if (name.back() == '/') return FsError{FsRefusal::bad_name, "names a folder"};
  const std::size_t slash = name.rfind('/');
  std::string leaf(slash == std::string_view::npos ? name : name.substr(slash + 1));
  if (leaf == "." || leaf == "..") return FsError{FsRefusal::bad_name, "names a folder"};
  const std::string_view folder = slash == std::string_view::npos ? std::string_view(".") : name.substr(0, slash + 1);
  auto dir = resolve(folder, O_PATH | O_DIRECTORY);
  if (!dir) return dir.error;
  return std::pair<UniqueFd, std::string>(std::move(*dir.value), std::move(leaf));
}

FsResult<UniqueFd> ConfinedFolder::open_read(std::string_view name) const { return open_regular(name, O_RDONLY); }

FsResult<UniqueFd> ConfinedFolder::open_append(std::string_view name) const {
  // Another writer may create the file between our look and our create: then it is there to
  // open (a few rounds; a name that stays taken and unopenable is a link to nothing).
  for (int attempt = 0; attempt < 4; ++attempt) {
    auto existing = open_regular(name, O_WRONLY | O_APPEND);
    if (existing || existing.error.kind != FsRefusal::not_found) return existing;
    auto parent = parent_of(name);
    if (!parent) return parent.error;
    auto& [dir, leaf] = *parent.value;
    const int fd = ::openat(dir.get(), leaf.c_str(), O_WRONLY | O_APPEND | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC | O_NOCTTY, 0666);
    if (fd >= 0) return UniqueFd(fd);
    if (errno != EEXIST) return error_of(errno);
  }
  return FsError{FsRefusal::not_regular, "is a link to a file that does not exist"};
}

FsResult<NewFile> ConfinedFolder::create(std::string_view name, bool replace) const {
  auto parent = parent_of(name);
  if (!parent) return parent.error;
  auto& [dir, leaf] = *parent.value;
  struct stat st {};
  if (::fstatat(dir.get(), leaf.c_str(), &st, AT_SYMLINK_NOFOLLOW) == 0) {
    if (!replace) return FsError{FsRefusal::exists, "exists already"};
    if (!S_ISREG(st.st_mode)) return S_ISLNK(st.st_mode) ? FsError{FsRefusal::not_regular, "is a link"} : kind_error(st.st_mode);
  } else if (errno != ENOENT) {
    return error_of(errno);
  }
  static unsigned serial = 0;
  for (int attempt = 0; attempt < 100; ++attempt) {
    std::string temp = "." + leaf + ".tmp." + std::to_string(::getpid()) + "." + std::to_string(++serial);
    if (temp.size() > 255) temp = ".asimov.tmp." + std::to_string(::getpid()) + "." + std::to_string(serial);
    const int fd = ::openat(dir.get(), temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC | O_NOCTTY, 0666);
    if (fd >= 0) return NewFile(std::move(dir), UniqueFd(fd), std::move(temp), std::move(leaf), replace);
    if (errno != EEXIST) return error_of(errno);
  }
  return FsError{FsRefusal::io, "no temporary name is free beside it"};
}

FsResult<FsDone> ConfinedFolder::truncate(std::string_view name) const {
  auto fd = open_regular(name, O_WRONLY);
  if (!fd) return fd.error;
  if (::ftruncate(fd.value->get(), 0) != 0) return error_of(errno);
  return FsDone{};
}

FsResult<FsDone> ConfinedFolder::remove(std::string_view name) const {
  auto parent = parent_of(name);
  if (!parent) return parent.error;
  auto& [dir, leaf] = *parent.value;
  struct stat st {};
  if (::fstatat(dir.get(), leaf.c_str(), &st, AT_SYMLINK_NOFOLLOW) != 0) return error_of(errno);
  if (!S_ISREG(st.st_mode) && !S_ISLNK(st.st_mode)) return kind_error(st.st_mode);
  if (::unlinkat(dir.get(), leaf.c_str(), 0) != 0) return error_of(errno);
  return FsDone{};
}

FsResult<std::vector<std::string>> ConfinedFolder::list(std::string_view name, std::size_t limit) const {
  auto probe = resolve(name, O_PATH);
  if (!probe) return probe.error;
  struct stat st {};
  if (::fstat(probe.value->get(), &st) != 0) return error_of(errno);
  if (!S_ISDIR(st.st_mode)) return FsError{FsRefusal::not_regular, "is not a folder"};
  auto fd = resolve(name, O_RDONLY | O_DIRECTORY);
  if (!fd) return fd.error;
  DIR* d = ::fdopendir(fd.value->get());
  if (!d) return error_of(errno);
  fd.value->release();  // the DIR owns the descriptor now
  std::vector<std::string> names;
  while (const dirent* e = ::readdir(d)) {
    const std::string_view n = e->d_name;
    if (n == "." || n == "..") continue;
    if (names.size() == limit) {
      ::closedir(d);
      return FsError{FsRefusal::io, "holds more than " + std::to_string(limit) + " names"};
    }
    names.emplace_back(n);
  }
  ::closedir(d);
  std::sort(names.begin(), names.end());
  return names;
}

bool ConfinedFolder::is_file(std::string_view name) const {
  auto probe = resolve(name, O_PATH);
  struct stat st {};
  return probe && ::fstat(probe.value->get(), &st) == 0 && S_ISREG(st.st_mode);
}

NewFile::NewFile(UniqueFd folder, UniqueFd fd, std::string temp, std::string name, bool replace)
    : folder_(std::move(folder)), fd_(std::move(fd)), temp_(std::move(temp)), name_(std::move(name)), replace_(replace) {}

NewFile::~NewFile() { discard(); }

void NewFile::discard() {
  if (!fd_) return;
  fd_.reset();
  ::unlinkat(folder_.get(), temp_.c_str(), 0);
}

FsResult<FsDone> NewFile::commit() {
  if (!fd_) return FsError{FsRefusal::io, "was closed already"};
  if (::fsync(fd_.get()) != 0 && errno != EINVAL) {
    const int err = errno;
    discard();
    return error_of(err);
  }
  fd_.reset();
  int rc = 0;
  if (replace_) {
    rc = ::renameat(folder_.get(), temp_.c_str(), folder_.get(), name_.c_str());
  } else {
    rc = static_cast<int>(::syscall(SYS_renameat2, folder_.get(), temp_.c_str(), folder_.get(), name_.c_str(), RENAME_NOREPLACE));
    if (rc != 0 && (errno == EINVAL || errno == ENOSYS)) {
      // A file system without RENAME_NOREPLACE: a hard link fails the same way when the name is taken.
      rc = ::linkat(folder_.get(), temp_.c_str(), folder_.get(), name_.c_str(), 0);
      if (rc == 0) ::unlinkat(folder_.get(), temp_.c_str(), 0);
    }
  }
  if (rc != 0) {
    const int err = errno;
    ::unlinkat(folder_.get(), temp_.c_str(), 0);
    return error_of(err);
  }
  return FsDone{};
}

FsResult<FsDone> write_all(int fd, std::string_view bytes) {
  while (!bytes.empty()) {
    const ssize_t n = ::write(fd, bytes.data(), bytes.size());
    if (n < 0) {
      if (errno == EINTR) continue;
      return error_of(errno);
    }
    if (n == 0) return FsError{FsRefusal::io, std::strerror(ENOSPC)};
    bytes.remove_prefix(static_cast<std::size_t>(n));
  }
  return FsDone{};
}

FsResult<FsDone> append_whole(int fd, std::string_view bytes) {
  using namespace std::chrono;
  const auto give_up = steady_clock::now() + seconds(10);
  while (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    if (errno != EWOULDBLOCK && errno != EINTR) return error_of(errno);
    if (steady_clock::now() > give_up) return FsError{FsRefusal::io, "is locked by another process"};
    std::this_thread::sleep_for(milliseconds(1));
  }
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    const int err = errno;
    ::flock(fd, LOCK_UN);
    return error_of(err);
  }
  FsResult<FsDone> done = write_all(fd, bytes);
  if (!done && ::ftruncate(fd, st.st_size) != 0) done.error.why += " (and the part written could not be taken back)";
  ::flock(fd, LOCK_UN);
  return done;
}

}  // namespace asimov::core
