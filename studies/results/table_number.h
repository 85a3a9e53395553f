// hipfai — a cell of a stored table the studies read back (an FE run's fe.csv, a validation
// folder's steps.csv) as a number, NaN when it is not one: the tables hold names beside numbers
// and leave a cell empty where there is no value, and a reader decides what NaN means to it.
#pragma once

#include <exception>
#include <limits>
#include <string>

namespace hipfai::studies {

// The number the whole cell spells ("1.25", "nan", "inf", "-0"); NaN for an empty cell, a name or
// a number followed by other text, and for a number out of double's range.
inline double table_number(const std::string& cell) {
  try {
    std::size_t used = 0;
    const double value = std::stod(cell, &used);
    return used == cell.size() ? value : std::numeric_limits<double>::quiet_NaN();
  } catch (const std::exception&) {
    return std::numeric_limits<double>::quiet_NaN();
  }
}

}  // namespace hipfai::studies
