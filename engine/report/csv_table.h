#pragma once
// A CSV file as a table of strings (header row first), and typed column access with errors
// that name the file, the line and the column. Used by `refrax chart` and `refrax report`.
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace refrax {

struct CsvTable {
  std::string where;  // the file name, for error messages
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;  // each row has header.size() fields
  std::vector<int> lines;                      // the source line of each row (1 = the header)
};

// RFC 4180: comma separated, fields optionally in double quotes ("" inside quotes is one "),
// LF or CRLF line ends, blank lines skipped, unquoted fields trimmed of spaces.
// refrax::Error on an empty file, an unterminated quote, or a row whose field count differs
// from the header's.
CsvTable parseCsv(const std::string& text, const std::string& where);
CsvTable readCsv(const std::string& path);  // refrax::Error naming the path when unreadable

// Index of the named column; refrax::Error listing the columns when there is none.
size_t csvColumn(const CsvTable& table, const std::string& name);
// The number in row `row` of column `column`: nullopt for an empty cell, refrax::Error for
// text that is not a whole number ("3.2x", "abc"). "nan" and "inf" parse as themselves.
std::optional<double> csvNumber(const CsvTable& table, size_t row, size_t column);

// One CSV field, quoted when it holds a comma, a quote, a line end or edge spaces.
std::string csvField(const std::string& value);
// A whole CSV line (fields joined by commas, ending in '\n').
std::string csvLine(const std::vector<std::string>& fields);

}  // namespace refrax
