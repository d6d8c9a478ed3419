#include "solvers/train/training_history.h"

#include <glog/logging.h>

#include <cmath>
#include <filesystem>
#include <utility>

#include "core/base/atomic_file.h"
#include "core/base/input_error.h"

namespace es {

TrainingHistory::TrainingHistory(std::string path,
                                 std::vector<std::string> columns)
    : path_(std::move(path)) {
  table_.columns = {"iteration", "seconds"};
  table_.columns.insert(table_.columns.end(), columns.begin(), columns.end());
}

double TrainingHistory::Resume(int64_t iteration) {
  table_.rows.clear();
  if (!std::filesystem::exists(path_)) return 0;
  CsvTable old;
  try {
    old = ReadCsvTable(path_);
  } catch (const InputError&) {
    return 0;
  }
  if (old.columns != table_.columns) return 0;
  for (const auto& row : old.rows) {
    if (row[0] <= iteration) table_.rows.push_back(row);
  }
  return table_.rows.empty() ? 0 : table_.rows.back()[1];
}

void TrainingHistory::Add(int64_t iteration, double seconds,
                          const std::vector<double>& values) {
  CHECK_EQ(values.size() + 2, table_.columns.size());
  std::vector<double> row = {static_cast<double>(iteration), seconds};
  row.insert(row.end(), values.begin(), values.end());
  table_.rows.push_back(std::move(row));
}

void TrainingHistory::SetFinalMetrics(
    int64_t iteration, double seconds,
    const std::vector<std::pair<std::string, double>>& values) {
  if (table_.rows.empty() || table_.rows.back()[0] != iteration) {
    std::vector<double> row(table_.columns.size(), NAN);
    row[0] = static_cast<double>(iteration);
    row[1] = seconds;
    table_.rows.push_back(std::move(row));
  }
  for (const auto& [name, value] : values) {
    const int c = table_.Column(name);
    CHECK_GE(c, 0) << "no column " << name;
    table_.rows.back()[c] = value;
  }
}

void TrainingHistory::Write() const {
  WriteTextFileAtomically(path_, CsvText(table_));
}

}  // namespace es
