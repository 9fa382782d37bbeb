#include "files.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <system_error>
#include <unistd.h>

namespace asimov::interpreter {

namespace fs = std::filesystem;

std::optional<fs::path> resolve_inside(const fs::path& root, const std::string& path, std::string& why) {
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
  std::error_code ec;
  const fs::path base = fs::weakly_canonical(fs::absolute(root, ec), ec);
  if (ec) {
    why = fmt::format("the files folder {} cannot be used", root.string());
    return std::nullopt;
  }
  // weakly_canonical follows the links that exist, so a link leading out is caught as well.
  const fs::path full = fs::weakly_canonical(base / p, ec);
  const auto mismatch = std::mismatch(base.begin(), base.end(), full.begin(), full.end());
  if (ec || mismatch.first != base.end() || full == base) {
    why = fmt::format("\"{}\" leaves the program's folder", path);
    return std::nullopt;
  }
  return full;
}

bool FileUnits::attach(int lun) { return units_.try_emplace(lun).second; }

int FileUnits::free_unit() const {
  for (int lun = kFirstUnit; lun <= kLastUnit; ++lun)
    if (!units_.count(lun)) return lun;
  return -1;
}

bool FileUnits::commit(Unit& u, std::string& error) {
  if (u.mode != Open::write && u.mode != Open::append) return true;
  u.out.close();
  std::error_code ec;
  fs::rename(u.temp, u.target, ec);  // atomic replacement in the same folder
  if (ec) {
    fs::remove(u.temp, ec);
    error = fmt::format("{} could not be written", u.target.filename().string());
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
  const auto target = resolve_inside(root_, path, error);
  if (!target) return 0;
  std::error_code ec;
  const bool exists = fs::exists(*target, ec);
  u->target = *target;
  switch (mode) {
    case Open::read:
      if (!exists || fs::is_directory(*target, ec)) return u->status = kIoFileNotFound;
      u->in.open(*target, std::ios::binary);
      if (!u->in) return u->status = kIoFileNotFound;
      break;
    case Open::directory: {
      if (!fs::is_directory(*target, ec)) return u->status = kIoFileNotFound;
      u->entries.clear();
      for (const auto& e : fs::directory_iterator(*target, ec)) u->entries.push_back(e.path().filename().string());
      std::sort(u->entries.begin(), u->entries.end());
      u->next_entry = 0;
      break;
    }
    case Open::write:
    case Open::append: {
      if (mode == Open::write && exists) return u->status = kIoFileExists;
      if (!fs::is_directory(target->parent_path(), ec)) return u->status = kIoFileNotFound;
      u->temp = target->parent_path() / fmt::format(".{}.tmp.{}", target->filename().string(), ::getpid());
      if (mode == Open::append && exists) fs::copy_file(*target, u->temp, fs::copy_options::overwrite_existing, ec);
      u->out.open(u->temp, std::ios::binary | (mode == Open::append ? std::ios::app : std::ios::trunc));
      if (ec || !u->out) {
        error = fmt::format("{} could not be opened for writing", path);
        return 0;
      }
      break;
    }
    case Open::none: break;
  }
  u->mode = mode;
  return u->status = kIoOk;
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

int FileUnits::empty(int lun, const std::string& path, std::string& error) {
  if (!open_unit(lun, error)) return 0;
  const auto target = resolve_inside(root_, path, error);
  if (!target) return 0;
  std::error_code ec;
  if (!fs::exists(*target, ec)) return units_[lun].status = kIoFileNotFound;
  const fs::path temp = target->parent_path() / fmt::format(".{}.tmp.{}", target->filename().string(), ::getpid());
  { std::ofstream(temp, std::ios::binary | std::ios::trunc); }
  fs::rename(temp, *target, ec);
  if (ec) {
    error = fmt::format("{} could not be emptied", path);
    return 0;
  }
  return units_[lun].status = kIoOk;
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
  std::string record;
  int c = u->in.get();
  if (c == std::char_traits<char>::eof()) {
    u->status = kIoEndOfFile;
    return std::nullopt;
  }
  // A record ends at LF, CR LF, CR CR LF or a lone CR (as program files, dialect §1).
  for (; c != std::char_traits<char>::eof(); c = u->in.get()) {
    if (c == '\n') break;
    if (c == '\r') {
      if (u->in.peek() == '\n') u->in.get();
      else if (u->in.peek() == '\r') {
        u->in.get();
        if (u->in.peek() == '\n') u->in.get();
        else u->in.unget();
      }
      break;
    }
    record += static_cast<char>(c);
  }
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
  const int c = u->in.get();
  u->status = c == std::char_traits<char>::eof() ? kIoEndOfFile : kIoOk;
  return c == std::char_traits<char>::eof() ? kIoEndOfFile : c;
}

void FileUnits::write(int lun, const std::string& text, std::string& error) {
  Unit* u = open_unit(lun, error);
  if (!u) return;
  if (u->mode != Open::write && u->mode != Open::append) {
    error = fmt::format("logical unit {} has no file open for writing", lun);
    return;
  }
  u->out << text;
  u->status = u->out ? kIoOk : 0;
  if (!u->out) error = fmt::format("{} could not be written", u->target.filename().string());
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
}

}  // namespace asimov::interpreter
