// The controller's module format (dialect §1 "Modules as the controller stores them"): what
// Adept's tools write around the program text, undone before the lines are split, with every
// kept byte where it was so line and column numbers stay those of the file.
#pragma once
#include <string>
#include <string_view>

namespace asimov::interpreter {

// The program text of a stored module: a leading UTF-8 byte order mark dropped, the text ended
// at the first Ctrl-Z (0x1A, the end-of-file mark) when it starts a line or follows the last
// `.END`, and before the NULs that pad the last sector, and every form feed (0x0C) that stands among a line's leading or trailing blanks
// (the page break Adept's tools put between programs) made a blank. Other control characters
// are left for the parser to report by name.
std::string module_text(std::string_view source);

}  // namespace asimov::interpreter
