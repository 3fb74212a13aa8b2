// The report as Markdown and HTML, and its figures' data as JSON for the plot script.
#include <fmt/format.h>

#include <cctype>
#include <cmath>
#include <nlohmann/json.hpp>

#include "bushel/io/base64.hpp"
#include "bushel/io/xml_escape.hpp"
#include "bushel/report/report.hpp"

namespace bushel {

namespace {

std::string markdown_cell(const std::string& s) {
  std::string out;
  for (const char c : s) out += c == '|' ? std::string("\\|") : c == '\n' ? std::string(" ") : std::string(1, c);
  return out;
}

// A column of numbers ("815.3", "-1.3 %", "n/a") is right-aligned, one of words left-aligned.
std::vector<bool> numeric_columns(const ReportTable& t) {
  std::vector<bool> numeric(t.header.size(), !t.rows.empty());
  for (const auto& row : t.rows) {
    for (std::size_t i = 0; i < row.size() && i < numeric.size(); ++i) {
      const std::string& c = row[i];
      const bool number =
          c == "n/a" ||
          (!c.empty() &&
           (std::isdigit(static_cast<unsigned char>(c[0])) ||
            ((c[0] == '-' || c[0] == '+') && c.size() > 1 && std::isdigit(static_cast<unsigned char>(c[1])))) &&
           c.find_first_not_of("0123456789.eE+- %") == std::string::npos);
      numeric[i] = numeric[i] && number;
    }
  }
  return numeric;
}

std::string markdown_table(const ReportTable& t) {
  std::string out = "|";
  for (const std::string& h : t.header) out += fmt::format(" {} |", markdown_cell(h));
  out += "\n|";
  for (const bool right : numeric_columns(t)) out += right ? "--:|" : "---|";
  out += "\n";
  for (const auto& row : t.rows) {
    out += "|";
    for (const std::string& cell : row) out += fmt::format(" {} |", markdown_cell(cell));
    out += "\n";
  }
  return out;
}

// `code` spans of the Markdown text as <code> in HTML.
std::string html_text(const std::string& s) {
  std::string out;
  bool code = false;
  for (const char c : io::xml_escaped(s)) {
    if (c == '`') {
      out += code ? "</code>" : "<code>";
      code = !code;
    } else {
      out += c;
    }
  }
  return code ? out + "</code>" : out;
}

std::string html_table(const ReportTable& t) {
  std::string out = "<div class=\"wide\"><table>\n<tr>";
  for (const std::string& h : t.header) out += "<th>" + io::xml_escaped(h) + "</th>";
  out += "</tr>\n";
  const std::vector<bool> numeric = numeric_columns(t);
  for (const auto& row : t.rows) {
    out += "<tr>";
    for (std::size_t i = 0; i < row.size(); ++i) {
      out += fmt::format("{}{}</td>", numeric[i] ? "<td class=\"n\">" : "<td>", io::xml_escaped(row[i]));
    }
    out += "</tr>\n";
  }
  return out + "</table></div>\n";
}

nlohmann::ordered_json numbers(const std::vector<double>& v) {
  nlohmann::ordered_json a = nlohmann::ordered_json::array();
  for (const double x : v) a.push_back(std::isfinite(x) ? nlohmann::ordered_json(x) : nlohmann::ordered_json());
  return a;
}

}  // namespace

std::string report_markdown(const Report& report) {
  std::string out = fmt::format("# {}\n", report.title);
  for (const ReportSection& s : report.sections) {
    out += fmt::format("\n## {}\n", s.title);
    for (const ReportBlock& b : s.blocks) {
      switch (b.kind) {
        case ReportBlock::Kind::heading:
          out += fmt::format("\n### {}\n", b.text);
          break;
        case ReportBlock::Kind::text:
          out += fmt::format("\n{}\n", b.text);
          break;
        case ReportBlock::Kind::list:
          out += fmt::format("\n{}:\n\n", b.text);
          for (const std::string& item : b.items) out += fmt::format("- {}\n", item);
          break;
        case ReportBlock::Kind::table:
          out += fmt::format("\n{}", markdown_table(b.table));
          if (!b.text.empty()) out += fmt::format("\n*{}*\n", b.text);
          break;
        case ReportBlock::Kind::figure:
          out += fmt::format("\n![{0}]({1})\n\n*{0}*\n", b.text, b.figure.file);
          break;
      }
    }
  }
  return out;
}

std::string report_html(const Report& report,
                        const std::function<std::optional<std::string>(const std::string&)>& figure_bytes) {
  std::string out =
      "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>" + io::xml_escaped(report.title) +
      "</title>\n<style>\nbody { font-family: sans-serif; max-width: 70em; margin: 2em auto; padding: 0 1em; }\n"
      "table { border-collapse: collapse; margin: 0.5em 0; font-size: 90%; }\n"
      // (a wide table scrolls inside the page; long words in its cells break)
      "div.wide { max-width: 100%; overflow-x: auto; } td, th { overflow-wrap: anywhere; }\n"
      "th, td { border: 1px solid #bbb; padding: 0.2em 0.5em; }\nth { background: #eee; }\n"
      "td.n { text-align: right; font-variant-numeric: tabular-nums; }\n"
      "figure { margin: 1em 0; } img { max-width: 100%; } .caption { color: #444; font-style: italic; }\n"
      "</style>\n</head>\n<body>\n<h1>" +
      io::xml_escaped(report.title) + "</h1>\n";
  for (const ReportSection& s : report.sections) {
    out += "<h2>" + io::xml_escaped(s.title) + "</h2>\n";
    for (const ReportBlock& b : s.blocks) {
      switch (b.kind) {
        case ReportBlock::Kind::heading:
          out += "<h3>" + io::xml_escaped(b.text) + "</h3>\n";
          break;
        case ReportBlock::Kind::text:
          out += "<p>" + html_text(b.text) + "</p>\n";
          break;
        case ReportBlock::Kind::list:
          out += "<p>" + html_text(b.text) + ":</p>\n<ul>\n";
          for (const std::string& item : b.items) out += "<li>" + html_text(item) + "</li>\n";
          out += "</ul>\n";
          break;
        case ReportBlock::Kind::table:
          out += html_table(b.table);
          if (!b.text.empty()) out += "<p class=\"caption\">" + html_text(b.text) + "</p>\n";
          break;
        case ReportBlock::Kind::figure: {
          const std::optional<std::string> png = figure_bytes ? figure_bytes(b.figure.file) : std::nullopt;
          const std::string src = png ? "data:image/png;base64," + io::base64(*png) : io::xml_escaped(b.figure.file);
          out += "<figure><img src=\"" + src + "\" alt=\"" + io::xml_escaped(b.text) +
                 "\"><figcaption class=\"caption\">" + html_text(b.text) + "</figcaption></figure>\n";
          break;
        }
      }
    }
  }
  return out + "</body>\n</html>\n";
}

std::string report_figures_json(const Report& report) {
  nlohmann::ordered_json figures = nlohmann::ordered_json::array();
  for (const ReportFigure* f : report.figures()) {
    nlohmann::ordered_json series = nlohmann::ordered_json::array();
    for (const ReportSeries& s : f->series) {
      series.push_back({{"label", s.label}, {"x", numbers(s.x)}, {"y", numbers(s.y)}, {"yerr", numbers(s.yerr)}});
    }
    figures.push_back({{"file", f->file},
                       {"kind", f->kind},
                       {"title", f->title},
                       {"xlabel", f->xlabel},
                       {"ylabel", f->ylabel},
                       {"categories", f->categories},
                       {"series", series},
                       {"frames", f->frames}});
  }
  return figures.dump(1, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

}  // namespace bushel
