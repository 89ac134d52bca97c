#include "freestand/ground_motion_reader.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fmt/format.h>
#include <fstream>
#include <limits>
#include <optional>
#include <string_view>

#include "freestand/input_error.h"
#include "freestand/units.h"

namespace freestand {

namespace {

using freestand::fail;  // "path: what"; the overload below adds the line

[[noreturn]] void fail(const std::string& path, int line, const std::string& what) {
  throw InputError(fmt::format("{}:{}: {}", path, line, what));
}

MotionUnit find_unit(const RecordSource& src) {
  if (const auto unit = find_motion_unit(src.units)) return *unit;
  fail(src.path, fmt::format("unknown units '{}' (expected g, m/s^2, cm/s^2, mm/s^2, m/s, cm/s, rad/s^2 or rad/s)",
                             src.units));
}

// One line at a time, with its 1-based number, '\r' of CRLF files removed.
class LineReader {
 public:
  explicit LineReader(const std::string& path) : path_(path), in_(path) {
    if (!in_) fail(path, "cannot open file");
  }
  bool next() {
    if (!std::getline(in_, text_)) return false;
    ++line_;
    if (!text_.empty() && text_.back() == '\r') text_.pop_back();
    return true;
  }
  const std::string& text() const { return text_; }
  int line() const { return line_; }
  const std::string& path() const { return path_; }
  [[noreturn]] void fail_here(const std::string& what) const { fail(path_, line_, what); }

 private:
  std::string path_;   // for messages
  std::ifstream in_;   // the file
  std::string text_;   // current line
  int line_ = 0;       // current line number, 1-based
};

std::string_view trim(std::string_view s) {
  const auto blank = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; };
  while (!s.empty() && blank(s.front())) s.remove_prefix(1);
  while (!s.empty() && blank(s.back())) s.remove_suffix(1);
  return s;
}

// Tokens separated by any of `separators` (empty tokens dropped when
// `keep_empty` is false, as for whitespace; kept for CSV fields).
std::vector<std::string_view> split(std::string_view s, std::string_view separators,
                                    bool keep_empty) {
  std::vector<std::string_view> out;
  std::size_t begin = 0;
  while (begin <= s.size()) {
    const std::size_t end = std::min(s.find_first_of(separators, begin), s.size());
    const std::string_view token = trim(s.substr(begin, end - begin));
    if (keep_empty || !token.empty()) out.push_back(token);
    begin = end + 1;
  }
  return out;
}

std::vector<std::string_view> words(std::string_view s) { return split(s, " \t", false); }

// A whole token as a number (locale-independent; a leading '+' allowed), or
// nothing when it is not one. NaN and inf parse: callers reject them.
std::optional<double> parse_number(std::string_view token) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  double x = 0.0;
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), x);
  if (ec == std::errc::result_out_of_range) return std::numeric_limits<double>::infinity();
  if (ec != std::errc() || end != token.data() + token.size()) return std::nullopt;
  return x;
}

double number(const LineReader& r, std::string_view token) {
  const std::optional<double> x = parse_number(token);
  if (!x) r.fail_here(fmt::format("non-numeric token '{}'", token));
  if (!std::isfinite(*x)) r.fail_here(fmt::format("value '{}' is not a finite number", token));
  return *x;
}

bool any_numeric(const std::vector<std::string_view>& tokens) {
  return std::any_of(tokens.begin(), tokens.end(),
                     [](std::string_view t) { return parse_number(t).has_value(); });
}

bool is_comment_or_blank(std::string_view line) {
  line = trim(line);
  return line.empty() || line.front() == '#';
}

// Collects (t, value) rows, checking that time increases.
struct Rows {
  std::vector<double> t;      // s
  std::vector<double> value;  // file units
  int last_line = 0;          // line of the last row, for messages

  void add(const LineReader& r, double time, double value_in_file_units) {
    if (!t.empty() && !(time > t.back()))
      r.fail_here(fmt::format("time {} does not increase (line {} has {})", time, last_line,
                              t.back()));
    t.push_back(time);
    value.push_back(value_in_file_units);
    last_line = r.line();
  }
};

// The 1-based column number a spec gives ("" means 2), or nothing if not a number.
std::optional<std::size_t> column_number(const std::string& spec) {
  if (spec.empty()) return 2;
  const std::optional<double> x = parse_number(spec);
  if (!x || *x != std::floor(*x) || *x < 1.0 || *x > 1e6) return std::nullopt;
  return static_cast<std::size_t>(*x);
}

std::size_t value_column(const RecordSource& src) {
  const std::optional<std::size_t> c = column_number(src.column);
  if (!c || *c < 2)
    fail(src.path, fmt::format("column '{}' must be a column number >= 2 (column 1 is time)",
                               src.column));
  return *c;
}

// ---- PEER AT2 ---------------------------------------------------------------

struct At2Header {
  long npts = 0;    // number of values
  double dt = 0.0;  // s
};

// Units named on header line 3 ("... IN UNITS OF G"), as our unit name, or
// empty when the header names none we know.
std::string_view at2_header_units(std::string line) {
  std::transform(line.begin(), line.end(), line.begin(),
                 [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
  const std::size_t at = line.find("UNITS OF ");
  if (at == std::string::npos) return {};
  const std::vector<std::string_view> w = split(std::string_view(line).substr(at + 9), " \t.,", false);
  if (w.empty()) return {};
  if (w.front() == "G") return "g";
  if (w.front() == "CM/S/S" || w.front() == "CM/SEC/SEC" || w.front() == "CM/S^2") return "cm/s^2";
  if (w.front() == "CM/S" || w.front() == "CM/SEC") return "cm/s";
  return {};
}

// Line 4: "NPTS= 5590, DT= .01000 SEC" (old PEER and NGA, any spacing), or
// "5590 .01000 NPTS, DT": the two numbers on the line, NPTS first.
At2Header parse_at2_counts(const LineReader& r) {
  std::string upper = r.text();
  std::transform(upper.begin(), upper.end(), upper.begin(),
                 [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
  std::vector<double> numbers;
  for (std::string_view token : split(r.text(), " \t,=", false))
    if (const std::optional<double> x = parse_number(token)) numbers.push_back(*x);
  if (upper.find("NPTS") == std::string::npos || upper.find("DT") == std::string::npos ||
      numbers.size() != 2)
    r.fail_here("expected 'NPTS= <count>, DT= <step> SEC' on line 4 of an AT2 file");
  const double npts = numbers[0], dt = numbers[1];
  if (!(npts >= 1.0 && npts == std::floor(npts) && npts < 1e9))
    r.fail_here(fmt::format("NPTS= {} is not a positive whole number", npts));
  if (!(dt > 0.0 && std::isfinite(dt))) r.fail_here(fmt::format("DT= {} is not > 0", dt));
  return {static_cast<long>(npts), dt};
}

At2Header read_at2_header(LineReader& r, const RecordSource& src) {
  while (r.line() < 4) {
    if (!r.next()) r.fail_here("AT2 header ends before line 4 (NPTS, DT)");
    if (r.line() != 3) continue;
    const std::string_view stated = at2_header_units(r.text());
    if (!stated.empty() && stated != src.units)
      r.fail_here(fmt::format("header states units {}, but units '{}' were given", stated,
                              src.units));
  }
  return parse_at2_counts(r);
}

// Values row-wise after line 4; t_i = i DT. With no time column, DT cannot
// disagree with the data; NPTS must equal the number of values.
void read_at2(LineReader& r, const RecordSource& src, Rows& rows) {
  const At2Header h = read_at2_header(r, src);
  std::vector<double> values;
  values.reserve(static_cast<std::size_t>(h.npts));
  while (r.next()) {
    for (std::string_view token : words(r.text())) {
      if (static_cast<long>(values.size()) == h.npts)
        r.fail_here(fmt::format("more values than NPTS= {} (line 4)", h.npts));
      values.push_back(number(r, token));
    }
  }
  if (static_cast<long>(values.size()) != h.npts)
    fail(r.path(), 4, fmt::format("NPTS= {} but the file holds {} values", h.npts, values.size()));
  rows.t.resize(values.size());
  for (std::size_t i = 0; i < values.size(); ++i) rows.t[i] = static_cast<double>(i) * h.dt;
  rows.value = std::move(values);
  rows.last_line = r.line();
}

// ---- whitespace columns -----------------------------------------------------

// Leading lines with no numeric token (e.g. "time  accel") are a header and
// skipped; '#' lines and blank lines are skipped anywhere. Any other
// non-numeric token is an error, as is a line whose column count differs
// from the first data line's.
void read_columns(LineReader& r, const RecordSource& src, Rows& rows) {
  const std::size_t column = value_column(src);
  std::size_t width = 0;  // columns of the first data line
  int first_line = 0;     // its line number
  while (r.next()) {
    if (is_comment_or_blank(r.text())) continue;
    const std::vector<std::string_view> tokens = words(r.text());
    if (width == 0 && !any_numeric(tokens)) continue;  // header line
    if (column > tokens.size())
      r.fail_here(fmt::format("no column {}: the line has {} columns", column, tokens.size()));
    if (width == 0) {
      width = tokens.size();
      first_line = r.line();
    }
    if (tokens.size() != width)
      r.fail_here(fmt::format("{} columns, but line {} has {}", tokens.size(), first_line, width));
    double time = 0.0, value = 0.0;
    for (std::size_t c = 0; c < tokens.size(); ++c) {
      const double x = number(r, tokens[c]);
      if (c == 0) time = x;
      if (c + 1 == column) value = x;
    }
    rows.add(r, time, value);
  }
}

// ---- CSV --------------------------------------------------------------------

std::string_view unquote(std::string_view s) {
  if (s.size() >= 2 && s.front() == '"' && s.back() == '"') return s.substr(1, s.size() - 2);
  return s;
}

// The value column (0-based) named by the spec: a 1-based number or a header name.
std::size_t csv_column(const LineReader& r, const RecordSource& src,
                       const std::vector<std::string_view>& header) {
  if (const std::optional<std::size_t> c = column_number(src.column)) {
    if (*c < 2) fail(src.path, "column 1 of a CSV record is time; choose a value column >= 2");
    if (*c > header.size())
      r.fail_here(fmt::format("no column {}: the header has {} columns", *c, header.size()));
    return *c - 1;
  }
  for (std::size_t c = 1; c < header.size(); ++c)
    if (unquote(header[c]) == src.column) return c;
  r.fail_here(fmt::format("no column '{}' in the header", src.column));
}

// The first line that is not blank or a '#' comment is the header (column
// names); every later line has as many comma-separated fields, all numeric.
void read_csv(LineReader& r, const RecordSource& src, Rows& rows) {
  std::vector<std::string_view> header;
  std::string header_text;  // owns the header's characters
  while (header.empty() && r.next()) {
    if (is_comment_or_blank(r.text())) continue;
    header_text = r.text();
    header = split(header_text, ",", true);
    if (std::all_of(header.begin(), header.end(),
                    [](std::string_view f) { return parse_number(f).has_value(); }))
      r.fail_here("expected a CSV header line (column names), found numbers");
  }
  if (header.empty()) return;  // empty file: reported as an empty record
  const int header_line = r.line();
  const std::size_t column = csv_column(r, src, header);
  while (r.next()) {
    if (is_comment_or_blank(r.text())) continue;
    const std::vector<std::string_view> fields = split(r.text(), ",", true);
    if (fields.size() != header.size())
      r.fail_here(fmt::format("{} fields, but the header (line {}) has {}", fields.size(),
                              header_line, header.size()));
    std::vector<double> x(fields.size());
    for (std::size_t c = 0; c < fields.size(); ++c) x[c] = number(r, fields[c]);
    rows.add(r, x[0], x[column]);
  }
}

// ---- dispatch ---------------------------------------------------------------

std::string resolved_format(const RecordSource& src) {
  if (src.format != "auto") return src.format;
  const std::size_t dot = src.path.find_last_of('.');
  std::string ext = dot == std::string::npos ? "" : src.path.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == "at2") return "at2";
  if (ext == "csv") return "csv";
  return "columns";
}

}  // namespace

GroundRecord read_ground_record(const RecordSource& src) {
  const MotionUnit unit = find_unit(src);
  const std::string format = resolved_format(src);
  if (format != "at2" && format != "columns" && format != "csv")
    fail(src.path, fmt::format("unknown format '{}' (expected auto, at2, columns or csv)", format));
  if (format == "at2" && !src.column.empty())
    fail(src.path, "an AT2 file has one value column; do not give a column");
  LineReader reader(src.path);
  Rows rows;
  if (format == "at2") read_at2(reader, src, rows);
  if (format == "columns") read_columns(reader, src, rows);
  if (format == "csv") read_csv(reader, src, rows);
  if (rows.t.empty()) fail(src.path, fmt::format("empty record: no data in {} lines", reader.line()));
  if (rows.t.size() < 2)
    fail(src.path, rows.last_line, "only one sample: a record needs at least two");

  GroundRecord record;
  record.t = std::move(rows.t);
  record.value = std::move(rows.value);
  for (double& x : record.value) x *= unit.to_si;
  record.is_velocity = unit.is_velocity;
  record.source = format == "at2" ? src.path
                                  : fmt::format("{} (column {})", src.path,
                                                src.column.empty() ? "2" : src.column);
  return record;
}

namespace {

// Derivative at x of the parabola through (t[k], v[k]), k = i, i+1, i+2:
// the second-order three-point formula, also on uneven spacing.
double parabola_slope(const std::vector<double>& t, const std::vector<double>& v, std::size_t i,
                      double x) {
  const double t0 = t[i], t1 = t[i + 1], t2 = t[i + 2];
  return v[i] * ((x - t1) + (x - t2)) / ((t0 - t1) * (t0 - t2)) +
         v[i + 1] * ((x - t0) + (x - t2)) / ((t1 - t0) * (t1 - t2)) +
         v[i + 2] * ((x - t0) + (x - t1)) / ((t2 - t0) * (t2 - t1));
}

}  // namespace

std::vector<double> differentiate(const std::vector<double>& t, const std::vector<double>& v) {
  const std::size_t n = t.size();
  if (n != v.size() || n < 3)
    throw InputError(fmt::format("differentiate: {} times and {} velocities, need >= 3 of each",
                                 n, v.size()));
  std::vector<double> a(n);
  a[0] = parabola_slope(t, v, 0, t[0]);  // one-sided at the ends
  for (std::size_t i = 1; i + 1 < n; ++i) a[i] = parabola_slope(t, v, i - 1, t[i]);  // central
  a[n - 1] = parabola_slope(t, v, n - 3, t[n - 1]);
  return a;
}

}  // namespace freestand
