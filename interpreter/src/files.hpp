// File I/O of dialect §7a: logical units attached to the disk, files opened on them, records
// read and written. Every path goes through one core::ConfinedFolder (the program's folder, or
// `--files DIR`): the kernel resolves it beneath that folder, so nothing outside it is read,
// written or deleted, and only regular files are opened. FOPENW writes to a temporary beside
// the target that takes its name when the file is closed (FCLOSE, DETACH, the end of the run),
// so a reader never sees half a file; FOPENA appends each record in place, whole, under a lock.
#pragma once
#include "asimov/core/confined_folder.hpp"

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace asimov::interpreter {

// Said with every network or serial construct that stops (ATTACH "TCP", FOPEN, FCMND).
constexpr std::string_view kNetworkHint =
    "network and serial I/O are not simulated: run the programs that move the arm alone with --main NAME";
constexpr std::string_view kNetworkDevices[] = {"TCP", "UDP", "NET", "SERIAL"};  // SERIAL:n too

// IOSTAT values (dialect §7a): 1 done, 0 nothing done yet on the unit; negative: the codes of
// kErrorCodes (errors.cpp) that a program is expected to handle.
constexpr int kIoOk = 1;
constexpr int kIoEndOfFile = -504;      // *Unexpected end of file*
constexpr int kIoFileNotFound = -500;   // *File not found*
constexpr int kIoFileExists = -503;     // *File already exists*

// What a program's files may cost (docs/limits.md): one record read or written, every byte a
// run writes, the names one FOPEND lists.
struct FileLimits {
  std::size_t max_record_bytes = 64 * 1024;
  std::uint64_t max_written_bytes = 256ull << 20;
  std::size_t max_folder_names = 100'000;
};

// A V+ file name (`/` or `\` separators, blanks around it ignored) as a relative path: nullopt
// and `why` when it is empty, absolute or names a drive (`C:`, `D>`).
std::optional<std::string> relative_name(const std::string& path, std::string& why);

class FileUnits {
 public:
  enum class Open { none, read, write, append, directory };

  // The folder every path is resolved in; opened at the first file operation of a run.
  void set_root(std::filesystem::path root);
  void set_limits(const FileLimits& limits) { limits_ = limits; }
  // Tests: resolve by the walk instead of openat2 (core::ConfinedFolder::Resolver).
  void set_resolver(core::ConfinedFolder::Resolver r) { resolver_ = r; }

  // ATTACH (lun) "DISK": false when the unit is attached already. free_unit: the lowest unit
  // not attached, from kFirstUnit (ATTACH mode 4), -1 when none is left.
  static constexpr int kFirstUnit = 5;
  static constexpr int kLastUnit = 31;
  bool attach(int lun);
  int free_unit() const;
  bool attached(int lun) const { return units_.count(lun) > 0; }
  // DETACH: closes (commits) its file; false when it was not attached.
  bool detach(int lun, std::string& error);

  // FOPENR / FOPENW / FOPENA / FOPEND: IOSTAT's value (1, or kIoFileNotFound ...). A path that
  // leaves the folder or names no regular file, a unit not attached or with a file open
  // already: `error` (the program stops). FOPENW creates the file and fails when it exists, as
  // V+ does.
  int open(int lun, Open mode, const std::string& path, std::string& error);
  // FCLOSE: commits a written file; IOSTAT's value.
  int close(int lun, std::string& error);
  // FEMPTY: the file exists afterwards and is empty.
  int empty(int lun, const std::string& path, std::string& error) { return on_name(lun, path, error, false); }
  // FDELETE: removes a file (a link: the link); a missing one sets IOSTAT.
  int remove(int lun, const std::string& path, std::string& error) { return on_name(lun, path, error, true); }

  // READ: the next record (LF, CR LF or CR CR LF removed); nullopt at the end of the file
  // (IOSTAT kIoEndOfFile). The unit must hold a file open for reading (or a directory).
  std::optional<std::string> read_record(int lun, std::string& error);
  // GETC: the next byte, kIoEndOfFile at the end.
  int get_byte(int lun, std::string& error);
  // WRITE: appends `text` to the file open for writing or appending.
  void write(int lun, const std::string& text, std::string& error);

  int iostat(int lun) const;
  void set_iostat(int lun, int value);

  // The end of the run: every written file is committed, every unit detached, the folder let go.
  void close_all();

 private:
  struct Unit {
    Open mode = Open::none;
    std::string name;                      // as the program wrote it, for messages
    core::UniqueFd fd;                     // read, append
    std::optional<core::NewFile> created;  // write: the temporary that becomes the file
    std::string buffer;                    // read: bytes read ahead, from `next`
    std::size_t next = 0;
    bool at_end = false;
    std::vector<std::string> entries;      // FOPEND: the directory's names, read in order
    std::size_t next_entry = 0;
    int status = 0;                        // IOSTAT
  };
  Unit* open_unit(int lun, std::string& error);
  int on_name(int lun, const std::string& path, std::string& error, bool remove);
  const core::ConfinedFolder* folder(std::string& error);
  // At least `count` bytes of `u` are buffered from `next` on (false: the file ends before, or
  // `error` says why it could not be read).
  bool have(Unit& u, std::size_t count, std::string& error);
  static bool commit(Unit& u, std::string& error);

  std::filesystem::path root_ = ".";
  std::optional<core::ConfinedFolder> folder_;
  core::ConfinedFolder::Resolver resolver_ = core::ConfinedFolder::Resolver::kernel;
  FileLimits limits_;
  std::uint64_t written_ = 0;  // bytes written by this run
  std::map<int, Unit> units_;
};

}  // namespace asimov::interpreter
