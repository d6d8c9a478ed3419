// Draws training histories and result tables as PNG line charts (OpenCV
// drawing, no plotting dependency).
//
//   es_plot --history DIR/history.csv --out DIR
//       loss.png (every loss term vs iteration, log scale), psnr.png
//       (held-out PSNR vs training wall time) and gaussians.png (Gaussians
//       and dynamic Gaussians vs iteration), for the columns the file has.
//   es_plot --csv FILE[,FILE...] --x COLUMN --y COLUMN[,COLUMN...]
//           [--labels A,B] --out FILE.png
//       any tables: one curve per y column, or per file.

#include <gflags/gflags.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "apps/common/app_main.h"
#include "apps/common/flag_checks.h"
#include "core/io/csv_table.h"
#include "core/io/image_file.h"
#include "core/base/input_error.h"
#include "core/io/output_dir.h"
#include "core/viz/line_plot.h"

constexpr char kUsage[] =
    "Draws training histories and result tables as PNG line charts.\n"
    "  es_plot --history DIR/history.csv --out DIR [--prefix NAME_]\n"
    "  es_plot --csv FILE[,FILE...] --x COL --y COL[,COL...] "
    "[--labels A,B] --out FILE.png";

DEFINE_string(history, "",
              "A trainer's history.csv (es_static, es_train, "
              "es_flowinit's flow_history.csv); --out is then a directory.");
DEFINE_string(prefix, "",
              "With --history: prefix of the PNG names, e.g. "
              "static_ gives static_loss.png.");
DEFINE_string(csv, "",
              "Numeric CSV table(s) with a header, comma-separated (instead "
              "of --history); --out is then the PNG file. Several files: "
              "one curve per file.");
DEFINE_string(x, "", "With --csv: the x column.");
DEFINE_string(y, "", "With --csv: y column(s), comma-separated.");
DEFINE_string(labels, "",
              "With several --csv files: their curves' labels, "
              "comma-separated (default: the file names).");
DEFINE_string(title, "", "Title (default: from the file and columns).");
DEFINE_string(x_label, "", "x-axis label (default: the x column).");
DEFINE_string(y_label, "", "y-axis label (default: the y column(s)).");
DEFINE_bool(log_y, false, "With --csv: logarithmic y axis.");
DEFINE_string(out, "", "Output: a directory (--history) or a PNG (--csv).");
DEFINE_int32(width, 900, "Image width in pixels.");
DEFINE_int32(height, 560, "Image height in pixels.");

namespace es {
namespace {

std::vector<std::string> SplitList(const std::string& text) {
  std::vector<std::string> items;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) {
    if (!item.empty()) items.push_back(item);
  }
  return items;
}

PlotOptions Options(const std::string& title, const std::string& x_label,
                    const std::string& y_label, bool log_y) {
  PlotOptions o;
  o.title = FLAGS_title.empty() ? title : FLAGS_title;
  o.x_label = FLAGS_x_label.empty() ? x_label : FLAGS_x_label;
  o.y_label = FLAGS_y_label.empty() ? y_label : FLAGS_y_label;
  o.log_y = log_y;
  o.width = FLAGS_width;
  o.height = FLAGS_height;
  return o;
}

void Write(const std::string& path, const std::vector<PlotSeries>& series,
           const PlotOptions& options) {
  WriteImageAtomically(path, DrawLinePlot(series, options));
  std::printf("wrote %s\n", path.c_str());
}

bool HasValues(const CsvTable& table, const std::string& column) {
  if (table.Column(column) < 0) return false;
  const std::vector<double> v = table.Values(column);
  return std::any_of(v.begin(), v.end(),
                     [](double x) { return std::isfinite(x); });
}

// The last two components of a path: "model/history.csv" says which run
// without a long absolute prefix.
std::string ShortName(const std::string& path) {
  const std::filesystem::path p(path);
  const std::filesystem::path parent = p.parent_path().filename();
  return parent.empty() ? p.filename().string()
                        : (parent / p.filename()).string();
}

bool IsLoss(const std::string& column) {
  return column != "iteration" && column != "seconds" &&
         column != "gaussians" && column != "dynamic" &&
         column.rfind("psnr", 0) != 0;
}

void PlotHistory() {
  const CsvTable table = ReadCsvTable(FLAGS_history);
  for (const char* column : {"iteration", "seconds"}) {
    if (table.Column(column) < 0) {
      throw InputError(FLAGS_history + ": no '" + column +
                       "' column (not a training history)");
    }
  }
  PrepareOutputDirectory(FLAGS_out, "out");
  const std::string stem = FLAGS_out + "/" + FLAGS_prefix;
  const std::vector<double> iteration = table.Values("iteration");
  const std::vector<double> seconds = table.Values("seconds");

  std::vector<PlotSeries> losses;
  for (const std::string& c : table.columns) {
    if (IsLoss(c) && HasValues(table, c)) {
      losses.push_back({c, iteration, table.Values(c)});
    }
  }
  if (!losses.empty()) {
    Write(stem + "loss.png", losses,
          Options("training loss by term: " + ShortName(FLAGS_history),
                  "iteration", "loss (mean over the log interval)", true));
  }
  std::vector<PlotSeries> psnr;
  for (const char* c : {"psnr_test", "psnr_test_water"}) {
    if (HasValues(table, c)) {
      psnr.push_back({std::string(c) == "psnr_test" ? "held-out PSNR"
                                                    : "held-out water PSNR",
                      seconds, table.Values(c)});
    }
  }
  if (!psnr.empty()) {
    Write(stem + "psnr.png", psnr,
          Options("held-out PSNR vs training time: " + ShortName(FLAGS_history),
                  "training wall time (s)", "PSNR (dB)", false));
  }
  std::vector<PlotSeries> counts;
  for (const char* c : {"gaussians", "dynamic"}) {
    if (HasValues(table, c)) {
      counts.push_back(
          {std::string(c) == "gaussians" ? "Gaussians" : "dynamic (water)",
           iteration, table.Values(c)});
    }
  }
  if (!counts.empty()) {
    Write(stem + "gaussians.png", counts,
          Options("Gaussians: " + ShortName(FLAGS_history), "iteration",
                  "count", false));
  }
}

void PlotTables() {
  RequireFlag("x", FLAGS_x);
  RequireFlag("y", FLAGS_y);
  const std::vector<std::string> files = SplitList(FLAGS_csv);
  const std::vector<std::string> ys = SplitList(FLAGS_y);
  std::vector<std::string> labels = SplitList(FLAGS_labels);
  if (files.size() > 1 && ys.size() != 1) {
    throw InputError("--csv with several files needs exactly one --y column");
  }
  if (!labels.empty() && labels.size() != files.size()) {
    throw InputError("--labels=" + FLAGS_labels + ": " +
                     std::to_string(labels.size()) + " labels for " +
                     std::to_string(files.size()) + " files");
  }
  std::vector<PlotSeries> series;
  for (size_t f = 0; f < files.size(); ++f) {
    const CsvTable table = ReadCsvTable(files[f]);
    for (const std::string& c : ys) {
      if (table.Column(c) < 0) {
        throw InputError("--y=" + FLAGS_y + ": " + files[f] +
                         " has no column '" + c + "'");
      }
    }
    if (table.Column(FLAGS_x) < 0) {
      throw InputError("--x=" + FLAGS_x + ": " + files[f] + " has no column '" +
                       FLAGS_x + "'");
    }
    for (const std::string& c : ys) {
      std::string label = c;
      if (files.size() > 1) {
        label = labels.empty() ? std::filesystem::path(files[f]).stem().string()
                               : labels[f];
      }
      series.push_back({label, table.Values(FLAGS_x), table.Values(c)});
    }
  }
  Write(FLAGS_out, series,
        Options(FLAGS_y + " vs " + FLAGS_x, FLAGS_x, FLAGS_y, FLAGS_log_y));
}

int Run() {
  if (FLAGS_history.empty() == FLAGS_csv.empty()) {
    throw InputError("give exactly one of --history and --csv");
  }
  RequireFlag("out", FLAGS_out);
  RequireAtLeast("width", FLAGS_width, 200);
  RequireAtLeast("height", FLAGS_height, 150);
  RequireAtMost("width", FLAGS_width, 8000, "a plot, not a poster");
  RequireAtMost("height", FLAGS_height, 8000, "a plot, not a poster");
  if (!FLAGS_history.empty()) {
    PlotHistory();
  } else {
    PlotTables();
  }
  return 0;
}

}  // namespace
}  // namespace es

int main(int argc, char** argv) {
  return es::RunApp(argc, argv, kUsage, es::Run);
}
