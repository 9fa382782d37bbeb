// Stage 3, file I/O (file_statements.hpp, dialect §7a).
#include "file_statements.hpp"

#include "evaluator.hpp"
#include "limits.hpp"
#include "operators.hpp"
#include "terminal.hpp"

#include <fmt/format.h>

#include <cctype>

namespace asimov::interpreter {

void FileStatements::begin_run(const Limits& limits) {
  units_.set_root(limits.files_root);
  units_.set_limits({limits.max_record_bytes, limits.max_file_bytes});
}

double FileStatements::function(const Node& n) {
  const int lun = to_index(to_real(vm_.eval(n.kids[0]), "logical unit"));
  const double mode = n.kids.size() > 1 && n.kids[1].kind != NodeKind::absent ? to_real(vm_.eval(n.kids[1]), "mode") : 0;
  if (n.func == Func::iostat) {
    if (mode != 0) raise(Message::not_supported, fmt::format("IOSTAT(lun, {})", format_number(mode)));
    return static_cast<double>(units_.iostat(lun));
  }
  std::string error;
  const int c = units_.get_byte(lun, error);
  if (!error.empty()) raise(Message::illegal_value, "GETC: " + error);
  return static_cast<double>(c);
}

int FileStatements::unit_number(const Instr& in) {
  const int lun = to_index(to_real(vm_.eval(in.args[0]), "logical unit"));
  if (lun < 0 || lun > FileUnits::kLastUnit) raise(Message::illegal_value, fmt::format("logical unit {}", lun));
  return lun;
}

// ATTACH / DETACH / FOPENR ... / READ / WRITE on a disk unit. As on V+, what the program is
// expected to handle (end of file, a missing file) only sets IOSTAT; a path leaving the folder,
// a unit used wrongly and a device that is not simulated stop the program.
void FileStatements::execute(const Instr& in) {
  const std::size_t first_item = static_cast<std::size_t>(in.items);
  auto text_item = [&]() -> std::string {
    return first_item < in.args.size() ? to_string_value(vm_.eval(in.args[first_item])) : std::string();
  };
  std::string error;
  auto check = [&] {
    if (!error.empty()) raise(Message::illegal_value, fmt::format("{}: {}", in.target.text, error));
  };
  if (in.io == IoOp::attach) {
    std::string device;
    for (char c : text_item()) device += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    if (!device.empty() && device != "DISK" && device != "NFS") {
      bool network = false;
      for (std::string_view d : kNetworkDevices) network = network || device.rfind(d, 0) == 0;
      raise(Message::not_supported, fmt::format("ATTACH \"{}\"{}", device, network ? "; " + std::string(kNetworkHint) : ""));
    }
    const double mode = in.args.size() > 1 && first_item > 1 && in.args[1].kind != NodeKind::absent
        ? to_real(vm_.eval(in.args[1]), "ATTACH mode") : 0;
    int lun = 0;
    if (static_cast<int>(mode) & 4) {  // allocate the next free unit, returned in the variable
      if (in.args[0].kind != NodeKind::variable) raise(Message::illegal_value, "ATTACH mode 4 needs a variable for the unit");
      lun = units_.free_unit();
      if (lun < 0) raise(Message::illegal_value, "ATTACH: no logical unit left");
      vm_.store(in.args[0], static_cast<double>(lun));
    } else {
      lun = unit_number(in);
    }
    if (!units_.attach(lun)) raise(Message::illegal_value, fmt::format("ATTACH: logical unit {} is attached already", lun));
    units_.set_iostat(lun, kIoOk);
    return;
  }
  const int lun = unit_number(in);
  switch (in.io) {
    case IoOp::detach:
      if (!units_.detach(lun, error) && error.empty()) error = fmt::format("logical unit {} is not attached", lun);
      return check();
    case IoOp::fopenr: case IoOp::fopenw: case IoOp::fopena: case IoOp::fopend: {
      const FileUnits::Open mode = in.io == IoOp::fopenr ? FileUnits::Open::read
                                 : in.io == IoOp::fopenw ? FileUnits::Open::write
                                 : in.io == IoOp::fopena ? FileUnits::Open::append : FileUnits::Open::directory;
      units_.open(lun, mode, text_item(), error);
      return check();
    }
    case IoOp::fclose: units_.close(lun, error); return check();
    case IoOp::fempty: units_.empty(lun, text_item(), error); return check();
    case IoOp::fdelete: units_.remove(lun, text_item(), error); return check();
    case IoOp::read: {
      if (in.args.size() > 1 && first_item > 1 && in.args[1].kind != NodeKind::absent
          && to_real(vm_.eval(in.args[1]), "record number") != 0)
        raise(Message::not_supported, "READ of a numbered record");
      const auto record = units_.read_record(lun, error);
      check();
      if (!record) return;  // end of file: IOSTAT says so, the variables are unchanged
      const std::size_t count = in.args.size() - first_item;
      if (count == 1 && in.args[first_item].text[0] == '$') {  // the whole record
        if (record->size() > kMaxStringLength) raise(Message::illegal_value, "READ: record longer than 128 characters");
        return vm_.store(in.args[first_item], *record);
      }
      // Several variables (or a real): the record's fields, separated by blanks, tabs or commas.
      std::vector<std::string> fields;
      std::string field;
      for (char c : *record + ' ') {
        if (c == ' ' || c == '\t' || c == ',') {
          if (!field.empty()) fields.push_back(field);
          field.clear();
        } else {
          field += c;
        }
      }
      for (std::size_t k = 0; k < count; ++k) {
        const Node& target = in.args[first_item + k];
        if (k >= fields.size())
          raise(Message::illegal_value, fmt::format("READ: the record has {} fields for {} variables", fields.size(), count));
        if (target.text[0] == '$') {
          vm_.store(target, fields[k]);
          continue;
        }
        const auto v = parse_reply_number(fields[k]);
        if (!v) raise(Message::illegal_value, fmt::format("READ: \"{}\" is not a number", fields[k]));
        vm_.store(target, *v);
      }
      return;
    }
    case IoOp::write: {
      bool record_end = true;
      std::vector<Value> values;
      for (std::size_t k = first_item; k < in.args.size(); ++k) values.push_back(vm_.eval(in.args[k]));
      std::string text = format_items(in.formats, values, record_end);
      if (record_end) text += "\r\n";  // V+ records end with CR LF; /S leaves the record open
      units_.write(lun, text, error);
      return check();
    }
    case IoOp::attach:  // handled above
    case IoOp::abort: case IoOp::kill: case IoOp::cycle_end: case IoOp::release:  // task_instruction
      break;
  }
}

}  // namespace asimov::interpreter
