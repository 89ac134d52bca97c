#include "csv_cells.h"

#include <fmt/format.h>

#include <cctype>
#include <charconv>
#include <cmath>
#include <limits>

#include "freestand/input_error.h"

namespace freestand {
namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

bool is_nan_text(std::string_view cell) {
  return cell.empty() || (cell.size() == 3 && std::tolower(cell[0]) == 'n' &&
                          std::tolower(cell[1]) == 'a' && std::tolower(cell[2]) == 'n');
}

}  // namespace

std::vector<std::string_view> split_cells(std::string_view line) {
  std::vector<std::string_view> cells;
  for (std::size_t begin = 0;;) {
    const std::size_t comma = line.find(',', begin);
    cells.push_back(trim(line.substr(begin, comma == std::string_view::npos ? comma : comma - begin)));
    if (comma == std::string_view::npos) return cells;
    begin = comma + 1;
  }
}

double cell_value(std::string_view cell, const std::string& where, std::size_t column,
                  const std::string& name) {
  if (is_nan_text(cell)) return std::numeric_limits<double>::quiet_NaN();
  std::string_view digits = cell;
  if (digits.front() == '+') digits.remove_prefix(1);
  double x = 0;
  const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), x);
  if (ec != std::errc() || end != digits.data() + digits.size() || !std::isfinite(x))
    throw InputError(fmt::format("{}: column {} ('{}'): '{}' is not a finite number", where, column,
                                 name, cell));
  return x;
}

}  // namespace freestand
