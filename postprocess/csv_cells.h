#ifndef FREESTAND_POST_CSV_CELLS_H
#define FREESTAND_POST_CSV_CELLS_H

// Cells of comma-separated lines, shared by the recording and data readers.

#include <string>
#include <string_view>
#include <vector>

namespace freestand {

// The cells of one line, blanks around each trimmed.
std::vector<std::string_view> split_cells(std::string_view line);

// A cell as a number: NaN for an empty cell or nan (any case), which mean a
// lost sample. Throws InputError "where: column N ('name'): 'cell' is not a
// finite number" otherwise.
double cell_value(std::string_view cell, const std::string& where, std::size_t column,
                  const std::string& name);

}  // namespace freestand

#endif
