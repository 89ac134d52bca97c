#ifndef FREESTAND_POST_HTML_REPORT_H
#define FREESTAND_POST_HTML_REPORT_H

// A self-contained HTML report (docs/report.md): title, metadata, numbered
// sections with paragraphs, tables and figures (inline SVG from svg_plot.h),
// a small inline style sheet. The file references nothing outside itself: no
// script, font, image or style sheet is fetched.

#include <string>
#include <utility>
#include <vector>

namespace freestand {

enum class CellMark { none, good, bad };  // highlighting, e.g. within / beyond a tolerance

struct TableCell {
  std::string text;      // shown as it is (escaped)
  bool numeric = false;  // right-aligned, tabular figures
  CellMark mark = CellMark::none;
};
TableCell text_cell(std::string text, CellMark mark = CellMark::none);
// `significant` significant digits; "n/a" for NaN.
TableCell number_cell(double value, int significant = 4, CellMark mark = CellMark::none);
// A number with `significant` significant digits, plain below 10^6 and at or
// above 10^-3 in magnitude, in scientific notation otherwise; a true minus sign.
std::string format_number(double value, int significant);

struct Table {
  std::string caption;
  std::vector<std::string> header;
  std::vector<std::vector<TableCell>> rows;  // each as long as the header
};

class HtmlReport {
 public:
  explicit HtmlReport(std::string title);

  void add_metadata(std::string key, std::string value);
  // Starts a numbered section; what follows goes into it.
  void add_section(std::string heading);
  void add_paragraph(const std::string& text);
  // Throws std::invalid_argument for a row whose length differs from the header's.
  void add_table(const Table& table);
  // svg: markup from svg::render, inserted as it is; numbered, captioned.
  void add_figure(const std::string& svg, const std::string& caption);

  std::string html() const;
  // Writes html() to PATH.part and renames it to PATH, so PATH is either the
  // old file or the complete new one. Throws InputError naming the path.
  void write(const std::string& path) const;

 private:
  struct Section {
    std::string heading;
    std::string body;  // HTML
  };
  std::string& current_body();

  std::string title_;
  std::vector<std::pair<std::string, std::string>> metadata_;
  std::string preface_;            // content before the first section
  std::vector<Section> sections_;
  int figures_ = 0, tables_ = 0;
};

}  // namespace freestand

#endif
