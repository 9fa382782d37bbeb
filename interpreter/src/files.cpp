#include "files.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <unistd.h>

namespace asimov::interpreter {

namespace fs = std::filesystem;
using core::FsError;
using core::FsRefusal;

namespace {

// The program's words for a refusal of the folder: `"NAME" why`.
std::string refusal(const std::string& name, const FsError& e) {
  if (e.kind == FsRefusal::outside) return fmt::format("\"{}\" leaves the program's folder", name);
  return fmt::format("\"{}\" {}", name, e.why);
}

}  // namespace

std::optional<std::string> relative_name(const std::string& path, std::string& why) {
  std::string p = path;
  std::replace(p.begin(), p.end(), '\\', '/');  // V+ writes \dir\file
  while (!p.empty() && (p.back() == ' ' || p.back() == '\t')) p.pop_back();
  while (!p.empty() && (p.front() == ' ' || p.front() == '\t')) p.erase(p.begin());
  if (p.empty()) {
    why = "empty file name";
    return std::nullopt;
  }
  const std::size_t drive = p.find_first_of(":>");
  if (p.front() == '/' || (drive != std::string::npos && drive < p.find('/'))) {
    why = fmt::format("\"{}\" is not inside the program's folder (absolute path or drive)", path);
    return std::nullopt;
  }
  return p;
}

void FileUnits::set_root(fs::path root) {
  root_ = std::move(root);
  folder_.reset();
  written_ = 0;
}

const core::ConfinedFolder* FileUnits::folder(std::string& error) {
  if (folder_) return &*folder_;
  auto opened = core::ConfinedFolder::open(root_, resolver_);
  if (!opened) {
    error = fmt::format("the files folder {} cannot be used: it {}", root_.string(), opened.error.why);
    return nullptr;
  }
  folder_ = std::move(*opened.value);
  return &*folder_;
}

bool FileUnits::attach(int lun) { return units_.try_emplace(lun).second; }

int FileUnits::free_unit() const {
  for (int lun = kFirstUnit; lun <= kLastUnit; ++lun)
    if (!units_.count(lun)) return lun;
  return -1;
}

bool FileUnits::commit(Unit& u, std::string& error) {
  if (!u.created) return true;
  auto done = u.created->commit();
  u.created.reset();
  if (!done) {
    error = fmt::format("\"{}\" could not be written: {}", u.name, done.error.why);
    return false;
  }
  return true;
}

bool FileUnits::detach(int lun, std::string& error) {
  auto it = units_.find(lun);
  if (it == units_.end()) return false;
  const bool ok = commit(it->second, error);
  units_.erase(it);
  return ok;
}

FileUnits::Unit* FileUnits::open_unit(int lun, std::string& error) {
  auto it = units_.find(lun);
  if (it == units_.end()) {
    error = fmt::format("logical unit {} is not attached", lun);
    return nullptr;
  }
  return &it->second;
}

int FileUnits::open(int lun, Open mode, const std::string& path, std::string& error) {
  Unit* u = open_unit(lun, error);
  if (!u) return 0;
  if (u->mode != Open::none) {
    error = fmt::format("logical unit {} has a file open already", lun);
    return 0;
  }
  const auto name = relative_name(path, error);
  if (!name) return 0;
  const core::ConfinedFolder* dir = folder(error);
  if (!dir) return 0;
  // A missing file (or folder on the way) and an existing one for FOPENW are the program's to
  // handle (IOSTAT); everything else the folder refuses stops it.
  auto refused = [&](const FsError& e) {
    if (e.kind == FsRefusal::not_found) return u->status = kIoFileNotFound;
    if (e.kind == FsRefusal::exists) return u->status = kIoFileExists;
    error = refusal(path, e);
    return 0;
  };
  Unit fresh;
  fresh.name = path;
  switch (mode) {
    case Open::read: {
      auto fd = dir->open_read(*name);
      if (!fd) return refused(fd.error);
      fresh.fd = std::move(*fd.value);
      break;
    }
    case Open::directory: {
      auto names = dir->list(*name, limits_.max_folder_names);
      if (!names) return refused(names.error);
      fresh.entries = std::move(*names.value);
      break;
    }
    case Open::write: {
      auto created = dir->create(*name);
      if (!created) return refused(created.error);
      fresh.created.emplace(std::move(*created.value));
      break;
    }
    case Open::append: {
      auto fd = dir->open_append(*name);
      if (!fd) return refused(fd.error);
      fresh.fd = std::move(*fd.value);
      break;
    }
    case Open::none: break;
  }
  fresh.mode = mode;
  fresh.status = kIoOk;
  *u = std::move(fresh);
  return kIoOk;
}

int FileUnits::close(int lun, std::string& error) {
  Unit* u = open_unit(lun, error);
  if (!u) return 0;
  const bool ok = commit(*u, error);
  Unit fresh;
  fresh.status = kIoOk;
  *u = std::move(fresh);
  return ok ? kIoOk : 0;
}

// FEMPTY and FDELETE: one operation on a named file, no unit's file involved.
int FileUnits::on_name(int lun, const std::string& path, std::string& error, bool remove) {
  Unit* u = open_unit(lun, error);
  if (!u) return 0;
  const auto name = relative_name(path, error);
  if (!name) return 0;
  const core::ConfinedFolder* dir = folder(error);
  if (!dir) return 0;
  auto done = remove ? dir->remove(*name) : dir->truncate(*name);
  if (!done && done.error.kind == FsRefusal::not_found) return u->status = kIoFileNotFound;
  if (!done) {
    error = refusal(path, done.error);
    return 0;
  }
  return u->status = kIoOk;
}

bool FileUnits::have(Unit& u, std::size_t count, std::string& error) {
  while (u.buffer.size() - u.next < count) {
    if (u.at_end) return false;
    u.buffer.erase(0, u.next);  // what was consumed goes; the rest moves to the front
    u.next = 0;
    char chunk[16384];
    const ssize_t n = ::read(u.fd.get(), chunk, sizeof chunk);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      error = fmt::format("\"{}\" could not be read: {}", u.name, std::strerror(errno));
      return false;
    }
    if (n == 0) u.at_end = true;
    u.buffer.append(chunk, static_cast<std::size_t>(n));
  }
  return true;
}

std::optional<std::string> FileUnits::read_record(int lun, std::string& error) {
  Unit* u = open_unit(lun, error);
  if (!u) return std::nullopt;
  if (u->mode == Open::directory) {
    if (u->next_entry >= u->entries.size()) {
      u->status = kIoEndOfFile;
      return std::nullopt;
    }
    u->status = kIoOk;
    return u->entries[u->next_entry++];
  }
  if (u->mode != Open::read) {
    error = fmt::format("logical unit {} has no file open for reading", lun);
    return std::nullopt;
  }
  if (!have(*u, 1, error)) {
    if (error.empty()) u->status = kIoEndOfFile;
    return std::nullopt;
  }
  // A record ends at LF, CR LF, CR CR LF or a lone CR (as program files, dialect §1). Bytes are
  // taken a buffer at a time; a record longer than the limit stops the program without being
  // kept whole or shown.
  std::string record;
  while (have(*u, 1, error)) {
    const char* begin = u->buffer.data() + u->next;
    const char* end = u->buffer.data() + u->buffer.size();
    const char* stop = std::find_if(begin, end, [](char c) { return c == '\n' || c == '\r'; });
    record.append(begin, stop);
    u->next += static_cast<std::size_t>(stop - begin);
    if (record.size() > limits_.max_record_bytes) {
      error = fmt::format("a record of \"{}\" is longer than {} bytes", u->name, limits_.max_record_bytes);
      return std::nullopt;
    }
    if (stop == end) continue;
    if (u->buffer[u->next++] == '\r') {
      if (have(*u, 1, error) && u->buffer[u->next] == '\n') ++u->next;
      else if (have(*u, 2, error) && u->buffer[u->next] == '\r' && u->buffer[u->next + 1] == '\n') u->next += 2;
    }
    break;
  }
  if (!error.empty()) return std::nullopt;
  u->status = kIoOk;
  return record;
}

int FileUnits::get_byte(int lun, std::string& error) {
  Unit* u = open_unit(lun, error);
  if (!u) return 0;
  if (u->mode != Open::read) {
    error = fmt::format("logical unit {} has no file open for reading", lun);
    return 0;
  }
  if (!have(*u, 1, error)) {
    u->status = kIoEndOfFile;
    return kIoEndOfFile;
  }
  u->status = kIoOk;
  return static_cast<unsigned char>(u->buffer[u->next++]);
}

void FileUnits::write(int lun, const std::string& text, std::string& error) {
  Unit* u = open_unit(lun, error);
  if (!u) return;
  if (u->mode != Open::write && u->mode != Open::append) {
    error = fmt::format("logical unit {} has no file open for writing", lun);
    return;
  }
  if (text.size() > limits_.max_record_bytes) {
    error = fmt::format("a record of {} bytes is longer than {} bytes", text.size(), limits_.max_record_bytes);
    return;
  }
  if (written_ + text.size() > limits_.max_written_bytes) {
    error = fmt::format("the run's files would pass {} bytes in all (docs/limits.md)", limits_.max_written_bytes);
    return;
  }
  auto done = u->mode == Open::write ? core::write_all(u->created->fd(), text) : core::append_whole(u->fd.get(), text);
  if (!done) {
    u->status = 0;
    error = fmt::format("\"{}\" could not be written: {}{}", u->name, done.error.why,
                        u->mode == Open::append ? " (the file keeps what it held before this record)" : "");
    return;
  }
  written_ += text.size();
  u->status = kIoOk;
}

int FileUnits::iostat(int lun) const {
  const auto it = units_.find(lun);
  return it == units_.end() ? 0 : it->second.status;
}

void FileUnits::set_iostat(int lun, int value) {
  if (auto it = units_.find(lun); it != units_.end()) it->second.status = value;
}

void FileUnits::close_all() {
  std::string ignored;
  for (auto& [lun, u] : units_) commit(u, ignored);
  units_.clear();
  folder_.reset();
}

}  // namespace asimov::interpreter
