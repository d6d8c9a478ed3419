#ifndef EULERSPLAT_CORE_IO_CSV_TABLE_H_
#define EULERSPLAT_CORE_IO_CSV_TABLE_H_

#include <string>
#include <vector>

namespace es {

// A numeric table with a header row: training histories and benchmark
// results. A cell that holds no number (empty, "nan") is NaN, so a value
// measured only on some rows (held-out PSNR at eval steps) leaves gaps.
struct CsvTable {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;  // rows[i].size() == columns.size()

  // Index of `name` in columns, or -1.
  int Column(const std::string& name) const;
  // The column's values, one per row; CHECK-fails for an unknown name.
  std::vector<double> Values(const std::string& name) const;
};

// Reads a comma-separated table. Throws InputError naming the file and line
// for a missing file, an empty header, a row of the wrong width or a cell
// that is not a number.
CsvTable ReadCsvTable(const std::string& path);

// The table as CSV text: %.9g numbers, NaN as an empty cell.
std::string CsvText(const CsvTable& table);

}  // namespace es

#endif  // EULERSPLAT_CORE_IO_CSV_TABLE_H_
