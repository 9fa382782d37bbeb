// One folder that a program (or a studio workspace) may use, and nothing outside it
// (docs/design.md "Confinement"). The folder is opened once; every path is then resolved
// beneath that open folder by the kernel (openat2 with RESOLVE_BENEATH: a `..` past the folder,
// an absolute link and a link leading out all fail inside the kernel, so no check of ours can
// be argued with), or, where the kernel has no openat2, by `walk`: the same rule component by
// component with openat(O_NOFOLLOW), following only links that stay beneath. Only regular files
// are opened (a device, FIFO or socket is refused before it is opened for reading or writing),
// and files are written either whole (a temporary beside the target, renamed to it without
// replacing anything) or appended in place.
#pragma once
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace asimov::core {

// A file descriptor that closes itself.
class UniqueFd {
 public:
  UniqueFd() = default;
  explicit UniqueFd(int fd) : fd_(fd) {}
  UniqueFd(UniqueFd&& o) noexcept : fd_(std::exchange(o.fd_, -1)) {}
  UniqueFd& operator=(UniqueFd&& o) noexcept;
  UniqueFd(const UniqueFd&) = delete;
  UniqueFd& operator=(const UniqueFd&) = delete;
  ~UniqueFd();
  int get() const { return fd_; }
  explicit operator bool() const { return fd_ >= 0; }
  void reset();
  int release() { return std::exchange(fd_, -1); }  // the caller closes it now

 private:
  int fd_ = -1;
};

// Why a path was refused or an operation failed. The caller chooses what each kind means to it
// (the interpreter: not_found and exists set IOSTAT, the rest stop the program).
enum class FsRefusal : std::uint8_t {
  not_found,    // no such file (or a folder on the way is missing)
  exists,       // creating a file that exists
  outside,      // absolute, or leaves the folder through `..` or a link
  not_regular,  // a device, FIFO, socket or a link to nothing
  is_folder,    // a folder where a file is needed
  bad_name,     // empty, NUL byte, too long, ends in `/`, `.` or `..`, too many links
  io,           // the system refused (permission, full disk, ...): `why` has its text
};

struct FsError {
  FsRefusal kind = FsRefusal::io;
  std::string why;  // a phrase for the user: "leaves the folder", "is a FIFO", "No space left on device"
};

template <class T>
struct FsResult {
  std::optional<T> value;
  FsError error;
  FsResult(T v) : value(std::move(v)) {}
  FsResult(FsError e) : error(std::move(e)) {}
  explicit operator bool() const { return value.has_value(); }
};

struct FsDone {};  // the value of an operation that returns nothing

// A file being written whole (FOPENW, a studio save): the bytes go to `fd`, a temporary beside
// the target; commit() gives it the target's name only if that name is still free, discard()
// (or the destructor) removes it.
class NewFile {
 public:
  NewFile(UniqueFd folder, UniqueFd fd, std::string temp, std::string name, bool replace);
  NewFile(NewFile&&) noexcept = default;
  NewFile& operator=(NewFile&&) noexcept = default;
  ~NewFile();
  int fd() const { return fd_.get(); }
  const std::string& name() const { return name_; }
  FsResult<FsDone> commit();
  void discard();

 private:
  UniqueFd folder_;
  UniqueFd fd_;
  std::string temp_;
  std::string name_;
  bool replace_ = false;  // commit may replace an existing regular file (a studio save)
};

class ConfinedFolder {
 public:
  enum class Resolver : std::uint8_t { kernel, walk };

  // Opens `root` (which must be a folder). `preferred` kernel falls back to walk by itself when
  // the kernel has no openat2 (ENOSYS, or a filter refusing it); walk is there for such kernels
  // and for the tests that run every case both ways.
  static FsResult<ConfinedFolder> open(const std::filesystem::path& root, Resolver preferred = Resolver::kernel);

  const std::filesystem::path& path() const { return path_; }
  Resolver resolver() const { return resolver_; }

  // `name` is relative, `/`-separated. An existing regular file, for reading.
  FsResult<UniqueFd> open_read(std::string_view name) const;
  // An existing regular file, or a new one, opened to append in place (O_APPEND).
  FsResult<UniqueFd> open_append(std::string_view name) const;
  // A new file written whole under `name`. replace = false: refused (exists) when the name is
  // taken, and commit() refuses it if it is taken meanwhile; true: an existing regular file is
  // replaced at commit().
  FsResult<NewFile> create(std::string_view name, bool replace = false) const;
  // An existing regular file cut to length 0 (in place: one system call, nothing half-done).
  FsResult<FsDone> truncate(std::string_view name) const;
  // Removes a file (or a link, not what it points to); a folder is refused.
  FsResult<FsDone> remove(std::string_view name) const;
  // The names in a folder (without `.` and `..`), sorted; at most `limit`.
  FsResult<std::vector<std::string>> list(std::string_view name, std::size_t limit) const;
  // Whether `name` is an existing regular file (a link to one beneath the folder counts).
  bool is_file(std::string_view name) const;

 private:
  ConfinedFolder(UniqueFd fd, std::filesystem::path path, Resolver resolver)
      : fd_(std::move(fd)), path_(std::move(path)), resolver_(resolver) {}
  FsResult<UniqueFd> resolve(std::string_view name, int flags, unsigned mode = 0) const;
  FsResult<UniqueFd> open_regular(std::string_view name, int flags) const;
  // The folder that holds `name`'s last component (resolved beneath) and that component.
  FsResult<std::pair<UniqueFd, std::string>> parent_of(std::string_view name) const;

  UniqueFd fd_;
  std::filesystem::path path_;
  mutable Resolver resolver_ = Resolver::kernel;
};

// Writes all of `bytes` (short writes and EINTR retried).
FsResult<FsDone> write_all(int fd, std::string_view bytes);
// Appends `bytes` to a file opened by open_append as one unit: under an exclusive lock (other
// processes appending through this function wait, up to 10 s), and cut back to the file's old
// length when not all of it could be written (a full disk), so the file keeps whole records.
FsResult<FsDone> append_whole(int fd, std::string_view bytes);

}  // namespace asimov::core
