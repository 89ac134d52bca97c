#include "html_report.h"

#include "atomic_file.h"

#include <fmt/format.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <stdexcept>

#include "freestand/input_error.h"
#include "svg_plot.h"

namespace freestand {

namespace {

// Compact, print-friendly; system fonts only.
constexpr const char* kStyle = R"(
body{font-family:"DejaVu Sans","Liberation Sans",Arial,sans-serif;font-size:15px;line-height:1.45;
color:#1a1a1a;background:#fff;max-width:940px;margin:24px auto;padding:0 16px}
h1{font-size:24px;margin:0 0 12px}
h2{font-size:19px;margin:30px 0 10px;padding-bottom:3px;border-bottom:1px solid #bbb}
table{border-collapse:collapse;margin:8px 0 18px;font-size:14px}
th,td{border:1px solid #c8c8c8;padding:3px 9px;text-align:left;vertical-align:top}
th{background:#eef1f4}
td.num{text-align:right;font-variant-numeric:tabular-nums;white-space:nowrap}
td.good{background:#d6e9f8}
td.bad{background:#fbd5bd;font-weight:bold}
table.meta th{background:none;border:none;padding:1px 14px 1px 0;color:#555;font-weight:normal}
table.meta td{border:none;padding:1px 0}
caption{caption-side:top;text-align:left;padding-bottom:4px}
figure{margin:14px 0 22px}
figure svg{max-width:100%;height:auto;display:block}
figcaption{font-size:14px;margin-top:4px}
nav ol{margin:4px 0 0;padding-left:22px}
@media print{h2{break-after:avoid}figure,table{break-inside:avoid}}
)";

const char* mark_class(CellMark mark) {
  switch (mark) {
    case CellMark::good: return "good";
    case CellMark::bad: return "bad";
    default: return "";
  }
}

std::string table_html(const Table& table, int number) {
  std::string out = "<table>";
  out += fmt::format("<caption><b>Table {}.</b> {}</caption>", number, svg::escape(table.caption));
  out += "<thead><tr>";
  for (const std::string& h : table.header) out += "<th>" + svg::escape(h) + "</th>";
  out += "</tr></thead><tbody>";
  for (const auto& row : table.rows) {
    out += "<tr>";
    for (const TableCell& cell : row) {
      std::string classes = cell.numeric ? "num" : "";
      if (cell.mark != CellMark::none) classes += (classes.empty() ? "" : " ") + std::string(mark_class(cell.mark));
      out += classes.empty() ? "<td>" : "<td class=\"" + classes + "\">";
      out += svg::escape(cell.text) + "</td>";
    }
    out += "</tr>";
  }
  return out + "</tbody></table>\n";
}

}  // namespace

TableCell text_cell(std::string text, CellMark mark) { return {std::move(text), false, mark}; }

TableCell number_cell(double value, int significant, CellMark mark) {
  return {format_number(value, significant), true, mark};
}

std::string format_number(double value, int significant) {
  if (std::isnan(value)) return "n/a";
  if (std::isinf(value)) return value > 0 ? "\u221E" : "\u2212\u221E";
  significant = std::max(significant, 1);
  const double magnitude = std::abs(value);
  std::string text;
  if (value == 0) {
    text = "0";
  } else if (magnitude >= 1e6 || magnitude < 1e-3) {
    text = fmt::format("{:.{}e}", value, significant - 1);
  } else {
    const int integer_digits = static_cast<int>(std::floor(std::log10(magnitude))) + 1;
    text = fmt::format("{:.{}f}", value, std::max(0, significant - integer_digits));
  }
  if (text[0] == '-') text = "\u2212" + text.substr(1);
  return text;
}

HtmlReport::HtmlReport(std::string title) : title_(std::move(title)) {}

void HtmlReport::add_metadata(std::string key, std::string value) {
  metadata_.emplace_back(std::move(key), std::move(value));
}

void HtmlReport::add_section(std::string heading) { sections_.push_back({std::move(heading), ""}); }

std::string& HtmlReport::current_body() { return sections_.empty() ? preface_ : sections_.back().body; }

void HtmlReport::add_paragraph(const std::string& text) {
  current_body() += "<p>" + svg::escape(text) + "</p>\n";
}

void HtmlReport::add_table(const Table& table) {
  for (std::size_t r = 0; r < table.rows.size(); ++r)
    if (table.rows[r].size() != table.header.size())
      throw std::invalid_argument(fmt::format("table '{}', row {}: {} cells for {} columns", table.caption,
                                              r + 1, table.rows[r].size(), table.header.size()));
  current_body() += table_html(table, ++tables_);
}

void HtmlReport::add_figure(const std::string& svg, const std::string& caption) {
  if (svg.rfind("<svg", 0) != 0)
    throw std::invalid_argument(fmt::format("figure '{}': not SVG markup", caption));
  current_body() += fmt::format("<figure>{}<figcaption><b>Figure {}.</b> {}</figcaption></figure>\n", svg,
                                ++figures_, svg::escape(caption));
}

std::string HtmlReport::html() const {
  std::string out = fmt::format(
      "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
      "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
      "<title>{0}</title>\n<style>{1}</style>\n</head>\n<body>\n<h1>{0}</h1>\n",
      svg::escape(title_), kStyle);
  if (!metadata_.empty()) {
    out += "<table class=\"meta\">";
    for (const auto& [key, value] : metadata_)
      out += "<tr><th>" + svg::escape(key) + "</th><td>" + svg::escape(value) + "</td></tr>";
    out += "</table>\n";
  }
  if (sections_.size() > 1) {
    out += "<nav><b>Contents</b><ol>";
    for (std::size_t i = 0; i < sections_.size(); ++i)
      out += fmt::format("<li><a href=\"#s{}\">{}</a></li>", i + 1, svg::escape(sections_[i].heading));
    out += "</ol></nav>\n";
  }
  out += preface_;
  for (std::size_t i = 0; i < sections_.size(); ++i)
    out += fmt::format("<section id=\"s{0}\">\n<h2>{0}. {1}</h2>\n{2}</section>\n", i + 1,
                       svg::escape(sections_[i].heading), sections_[i].body);
  return out + "</body>\n</html>\n";
}

void HtmlReport::write(const std::string& path) const { write_file_atomically(path, html()); }

}  // namespace freestand
