#ifndef EULERSPLAT_SOLVERS_TRAIN_TRAINING_HISTORY_H_
#define EULERSPLAT_SOLVERS_TRAIN_TRAINING_HISTORY_H_

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "core/io/csv_table.h"

namespace es {

// A trainer's history.csv: one row per logged iteration with the columns
// "iteration", "seconds" (training wall time, evaluation excluded, so the
// curve does not depend on how often one evaluates) and the trainer's own
// (losses by term, Gaussians, held-out PSNR; NaN where not measured). The
// whole file is rewritten atomically on every Write, so a killed run leaves
// a valid file. es_plot draws it.
class TrainingHistory {
 public:
  TrainingHistory(std::string path, std::vector<std::string> columns);

  // Continues the file of an interrupted run resumed at `iteration`: keeps
  // its rows up to that iteration (later ones were lost with the
  // checkpoint) and returns the seconds of the last kept row, from which the
  // resumed run's clock continues (0 when there is no usable file: a
  // missing file, or one with other columns, starts afresh).
  double Resume(int64_t iteration);

  // Appends a row; `values` in the order of the constructor's columns.
  void Add(int64_t iteration, double seconds,
           const std::vector<double>& values);
  // The run's final held-out metrics: into the row of `iteration` when the
  // history ends there (a run resumed at its end), else a new row with them
  // and NaN for everything else. `values`: column name -> value.
  void SetFinalMetrics(
      int64_t iteration, double seconds,
      const std::vector<std::pair<std::string, double>>& values);
  // Writes the file (atomically); throws InputError on failure.
  void Write() const;

  const CsvTable& table() const { return table_; }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  CsvTable table_;
};

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_TRAIN_TRAINING_HISTORY_H_
