#include "data_section.hpp"

#include "checker.hpp"
#include "limits.hpp"
#include "parser.hpp"

#include <fmt/format.h>

namespace asimov::interpreter {

Result<DataItem> compile_data_line(const ast::DataLine& d, ast::Kw section, int joint_count, Symbols& symbols) {
  auto fail = [](std::string text) -> Result<DataItem> { return Error{std::move(text), {}, {}, 0}; };
  DataItem item;
  const std::string name = normalize_name(d.name);
  const char prefix = name.empty() ? '\0' : name[0];
  if (d.indices.size() > static_cast<std::size_t>(kMaxSubscripts)) return fail("at most 3 subscripts");
  for (std::size_t k = 0; k < d.indices.size(); ++k) {
    if (d.indices[k] < 0 || d.indices[k] > kMaxArrayIndex) return fail("index outside 0 to 65535");
    item.index[k] = d.indices[k];
  }
  item.subscripted = !d.indices.empty();
  const std::size_t n = d.values.size();
  switch (section) {
    case ast::Kw::dot_locations:
      if (d.text || prefix == '$') return fail("a location takes numbers");
      if (prefix == '#') {
        if (n != static_cast<std::size_t>(joint_count))
          return fail(fmt::format("a precision point takes {} joint values", joint_count));
        robots::JointVector j(joint_count);
        for (std::size_t k = 0; k < n; ++k) j[static_cast<Eigen::Index>(k)] = d.values[k];
        item.value = j;
      } else {
        if (n != 6) return fail("a transformation takes x, y, z, o, a, t");
        item.value = motion::trans(d.values[0], d.values[1], d.values[2], d.values[3], d.values[4], d.values[5]);
      }
      break;
    case ast::Kw::dot_reals:
      if (d.text || prefix == '$' || prefix == '#' || n != 1) return fail("a real takes one number");
      item.value = d.values[0];
      break;
    default:  // .STRINGS
      if (prefix != '$' || !d.text || n != 0) return fail("a string takes a $name and a \"text\"");
      if (d.text->size() > kMaxStringLength) return fail("string longer than 128 characters");
      item.value = *d.text;
      break;
  }
  item.slot = symbols.global(name);
  return item;
}

}  // namespace asimov::interpreter
