#include "app/atomic_file.hpp"

#include "asimov/core/output_file.hpp"

namespace asimov::app {

Result<void> write_file_atomically(const std::string& path, const std::string& text) {
  return core::write_output_file(path, text);
}

}  // namespace asimov::app
