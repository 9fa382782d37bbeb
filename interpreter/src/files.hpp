// Confined file I/O of dialect §7a: logical units attached to the disk, files opened on them,
// records read and written. Every path is resolved inside one folder (the program's, or
// `--files DIR`); writes go to a temporary file beside the target and replace it when the file
// is closed (FCLOSE, DETACH, the end of the run), so a reader never sees half a file.
#pragma once
#include <filesystem>
#include <fstream>
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

// `path` (V+ spelling: `/` or `\` separators) inside `root`: nullopt and `why` when it is
// absolute, names a drive (`C:`, `D>`), or leaves `root` (through `..` or a link).
std::optional<std::filesystem::path> resolve_inside(const std::filesystem::path& root, const std::string& path,
                                                    std::string& why);

class FileUnits {
 public:
  enum class Open { none, read, write, append, directory };

  void set_root(std::filesystem::path root) { root_ = std::move(root); }
  const std::filesystem::path& root() const { return root_; }

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
  // leaves the folder, a unit not attached or with a file open already: `error` (the program
  // stops). FOPENW creates the file and fails when it exists, as V+ does.
  int open(int lun, Open mode, const std::string& path, std::string& error);
  // FCLOSE: commits a written file; IOSTAT's value.
  int close(int lun, std::string& error);
  // FEMPTY: the file exists afterwards and is empty (through the same atomic replacement).
  int empty(int lun, const std::string& path, std::string& error);

  // READ: the next record (LF, CR LF or CR CR LF removed); nullopt at the end of the file
  // (IOSTAT kIoEndOfFile). The unit must hold a file open for reading (or a directory).
  std::optional<std::string> read_record(int lun, std::string& error);
  // GETC: the next byte, kIoEndOfFile at the end.
  int get_byte(int lun, std::string& error);
  // WRITE: appends `text` to the file open for writing or appending.
  void write(int lun, const std::string& text, std::string& error);

  int iostat(int lun) const;
  void set_iostat(int lun, int value);

  // The end of the run: every written file is committed, every unit detached.
  void close_all();

 private:
  struct Unit {
    Open mode = Open::none;
    std::filesystem::path target;   // the file (or directory) opened
    std::filesystem::path temp;     // writes: the temporary file renamed over `target`
    std::ifstream in;
    std::ofstream out;
    std::vector<std::string> entries;  // FOPEND: the directory's names, read in order
    std::size_t next_entry = 0;
    int status = 0;                 // IOSTAT
  };
  Unit* open_unit(int lun, std::string& error);
  static bool commit(Unit& u, std::string& error);

  std::filesystem::path root_ = ".";
  std::map<int, Unit> units_;
};

}  // namespace asimov::interpreter
