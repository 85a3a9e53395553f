// hipfai — one line of a comma-separated table split into its cells (no quoting: the project's
// tables hold numbers and plain names). Each cell is trimmed of blanks and a trailing '\r'; a line
// ending in ',' has an empty last cell, so a row keeps its width when its last value is missing.
#pragma once

#include <string>
#include <vector>

namespace hipfai {

std::vector<std::string> split_csv_line(const std::string& line);

}  // namespace hipfai
