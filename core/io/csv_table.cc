#include "core/io/csv_table.h"

#include <glog/logging.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "core/base/input_error.h"

namespace es {
namespace {

std::vector<std::string> SplitCells(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream in(line);
  std::string cell;
  while (std::getline(in, cell, ',')) cells.push_back(cell);
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

std::string Trim(const std::string& s) {
  const size_t a = s.find_first_not_of(" \t\r");
  if (a == std::string::npos) return "";
  return s.substr(a, s.find_last_not_of(" \t\r") - a + 1);
}

}  // namespace

int CsvTable::Column(const std::string& name) const {
  for (size_t i = 0; i < columns.size(); ++i) {
    if (columns[i] == name) return static_cast<int>(i);
  }
  return -1;
}

std::vector<double> CsvTable::Values(const std::string& name) const {
  const int c = Column(name);
  CHECK_GE(c, 0) << "no column " << name;
  std::vector<double> values;
  for (const auto& row : rows) values.push_back(row[c]);
  return values;
}

CsvTable ReadCsvTable(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open");
  CsvTable table;
  std::string line;
  if (!std::getline(in, line) || Trim(line).empty()) {
    throw InputError(path + ": empty file (expected a header row)");
  }
  for (const std::string& cell : SplitCells(line)) {
    table.columns.push_back(Trim(cell));
  }
  for (int number = 2; std::getline(in, line); ++number) {
    if (Trim(line).empty()) continue;
    const std::vector<std::string> cells = SplitCells(line);
    const std::string where = path + ":" + std::to_string(number);
    if (cells.size() != table.columns.size()) {
      throw InputError(where + ": " + std::to_string(cells.size()) +
                       " cells, the header has " +
                       std::to_string(table.columns.size()));
    }
    std::vector<double> row;
    for (const std::string& raw : cells) {
      const std::string cell = Trim(raw);
      if (cell.empty()) {
        row.push_back(NAN);
        continue;
      }
      char* end = nullptr;
      const double v = std::strtod(cell.c_str(), &end);
      if (end == cell.c_str() || *end != '\0') {
        throw InputError(where + ": '" + cell + "' is not a number");
      }
      row.push_back(v);
    }
    table.rows.push_back(std::move(row));
  }
  return table;
}

std::string CsvText(const CsvTable& table) {
  std::string out;
  for (size_t i = 0; i < table.columns.size(); ++i) {
    out += (i ? "," : "") + table.columns[i];
  }
  out += "\n";
  for (const auto& row : table.rows) {
    for (size_t i = 0; i < row.size(); ++i) {
      if (i) out += ",";
      if (std::isfinite(row[i])) {
        char text[32];
        std::snprintf(text, sizeof(text), "%.9g", row[i]);
        out += text;
      }
    }
    out += "\n";
  }
  return out;
}

}  // namespace es
