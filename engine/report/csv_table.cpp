#include "engine/report/csv_table.h"

#include <cerrno>
#include <cstdlib>

#include "engine/base/error.h"
#include "engine/io/atomic_file.h"

namespace refrax {

namespace {

std::string trimmed(const std::string& s) {
  size_t a = s.find_first_not_of(" \t"), b = s.find_last_not_of(" \t");
  return a == std::string::npos ? std::string() : s.substr(a, b - a + 1);
}

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (size_t i = 0; i < names.size(); i++) out += (i ? ", " : "") + names[i];
  return out;
}

}  // namespace

CsvTable parseCsv(const std::string& text, const std::string& where) {
  CsvTable t;
  t.where = where;
  std::vector<std::string> fields;
  std::string field;
  bool quoted = false;     // inside a quoted field
  bool wasQuoted = false;  // the current field was quoted (kept verbatim, not trimmed)
  bool any = false;        // the current line has content
  int line = 1, rowLine = 1;
  auto endField = [&] {
    fields.push_back(wasQuoted ? field : trimmed(field));
    field.clear();
    wasQuoted = false;
  };
  auto endRow = [&] {
    if (!any) return;  // a blank line
    endField();
    if (t.header.empty()) {
      t.header = fields;
    } else {
      if (fields.size() != t.header.size())
        fail(where + " line " + std::to_string(rowLine) + ": " + std::to_string(fields.size()) + " fields, the header has " +
             std::to_string(t.header.size()));
      t.rows.push_back(fields);
      t.lines.push_back(rowLine);
    }
    fields.clear();
    any = false;
  };
  for (size_t i = 0; i < text.size(); i++) {
    char c = text[i];
    if (quoted) {
      if (c == '"' && i + 1 < text.size() && text[i + 1] == '"') {
        field += '"';
        i++;
      } else if (c == '"') {
        quoted = false;
      } else {
        if (c == '\n') line++;
        field += c;
      }
      continue;
    }
    if (c == '"' && trimmed(field).empty()) {
      quoted = wasQuoted = any = true;
      field.clear();
    } else if (c == ',') {
      any = true;
      endField();
    } else if (c == '\n') {
      endRow();
      line++;
      rowLine = line;
    } else if (c != '\r') {
      if (!any && c != ' ' && c != '\t') any = true;
      field += c;
    }
  }
  if (quoted) fail(where + " line " + std::to_string(rowLine) + ": a quoted field is not closed");
  endRow();
  if (t.header.empty()) fail(where + " is empty (no header row)");
  for (size_t i = 0; i < t.header.size(); i++)
    if (t.header[i].empty()) fail(where + ": column " + std::to_string(i + 1) + " of the header has no name");
  return t;
}

CsvTable readCsv(const std::string& path) { return parseCsv(readFile(path), path); }

size_t csvColumn(const CsvTable& t, const std::string& name) {
  for (size_t i = 0; i < t.header.size(); i++)
    if (t.header[i] == name) return i;
  fail(t.where + " has no column '" + name + "' (columns: " + joined(t.header) + ")");
}

std::optional<double> csvNumber(const CsvTable& t, size_t row, size_t column) {
  const std::string& s = t.rows.at(row).at(column);
  if (s.empty()) return std::nullopt;
  char* end = nullptr;
  errno = 0;
  double v = std::strtod(s.c_str(), &end);
  if (end == s.c_str() || *end)
    fail(t.where + " line " + std::to_string(t.lines[row]) + ", column '" + t.header[column] + "': '" + s + "' is not a number");
  return v;
}

std::string csvField(const std::string& v) {
  bool quote = v.find_first_of(",\"\r\n") != std::string::npos || (!v.empty() && (v.front() == ' ' || v.back() == ' '));
  if (!quote) return v;
  std::string out = "\"";
  for (char c : v) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

std::string csvLine(const std::vector<std::string>& fields) {
  std::string out;
  for (size_t i = 0; i < fields.size(); i++) out += (i ? "," : "") + csvField(fields[i]);
  return out + "\n";
}

}  // namespace refrax
