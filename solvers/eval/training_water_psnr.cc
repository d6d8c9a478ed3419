#include "solvers/eval/training_water_psnr.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/base/input_error.h"
#include "core/io/csv_table.h"

namespace es {

namespace fs = std::filesystem;

TrainingWaterPsnr ReadTrainingWaterPsnr(const std::string& model_dir) {
  TrainingWaterPsnr p;
  const fs::path metrics = fs::path(model_dir) / "metrics.json";
  if (fs::exists(metrics)) {
    std::ifstream in(metrics);
    std::stringstream text;
    text << in.rdbuf();
    const nlohmann::json json =
        nlohmann::json::parse(text.str(), nullptr, /*allow_exceptions=*/false);
    if (json.is_discarded()) {
      throw InputError(metrics.string() + ": not valid JSON");
    }
    const auto read = [&json](const char* key, double* value) {
      const auto it = json.find(key);
      if (it != json.end() && it->is_number()) *value = it->get<double>();
    };
    read("stage1_psnr_test_water", &p.stage1);
    read("stage1_psnr_test_far_scenery", &p.stage1_far_scenery);
  }
  const fs::path history = fs::path(model_dir) / "history.csv";
  if (!fs::exists(history)) return p;
  const CsvTable table = ReadCsvTable(history.string());
  const int water = table.Column("psnr_test_water");
  const int iteration = table.Column("iteration");
  if (water < 0 || iteration < 0) return p;
  for (const std::vector<double>& row : table.rows) {
    if (!std::isfinite(row[water])) continue;
    if (p.first_iteration < 0) {
      p.first = row[water];
      p.first_iteration = static_cast<int64_t>(row[iteration]);
    }
    p.last = row[water];
    p.last_iteration = static_cast<int64_t>(row[iteration]);
  }
  return p;
}

nlohmann::ordered_json TrainingWaterPsnrJson(const TrainingWaterPsnr& p) {
  const auto number = [](double v) -> nlohmann::ordered_json {
    return std::isfinite(v) ? nlohmann::ordered_json(v) : nullptr;
  };
  return {{"stage1", number(p.stage1)},
          {"stage3_first", number(p.first)},
          {"stage3_first_iteration", p.first_iteration},
          {"stage3_last", number(p.last)},
          {"stage3_last_iteration", p.last_iteration},
          {"stage1_far_scenery", number(p.stage1_far_scenery)}};
}

void PrintTrainingWaterPsnr(const TrainingWaterPsnr& p) {
  if (!std::isfinite(p.stage1) && p.first_iteration < 0) return;
  std::printf("  water PSNR, training  ");
  if (std::isfinite(p.stage1)) std::printf("Stage 1 %.2f dB -> ", p.stage1);
  if (p.first_iteration >= 0) {
    std::printf("Stage 3 %.2f dB (iteration %lld) -> %.2f dB (iteration "
                "%lld)",
                p.first, static_cast<long long>(p.first_iteration), p.last,
                static_cast<long long>(p.last_iteration));
    if (std::isfinite(p.stage1)) {
      std::printf("; %+.2f dB from Stage 1", p.last - p.stage1);
    }
  }
  std::printf("\n");
}

}  // namespace es
