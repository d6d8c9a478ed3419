#ifndef EULERSPLAT_SOLVERS_PIPELINE_STAGE_LOG_H_
#define EULERSPLAT_SOLVERS_PIPELINE_STAGE_LOG_H_

#include <chrono>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace es {

// Numbers the driver's stages "k/N" and says how long the run has taken,
// so a person sees where a long run stands; keeps each stage's wall time
// and CPU time (this process and the stage binaries it waited for) for
// OUT/timings.json.
class StageLog {
 public:
  // `total` stages follow; `seconds_before` were spent before the first
  // (frames, poses and masks), shown as a stage of their own.
  StageLog(int total, double seconds_before);

  // Ends the stage before (if any); prints "[eulersplat] stage k/N: name
  // (S s so far)".
  void Begin(const std::string& name);
  // The stage begun last found its outputs and did not run.
  void Skipped();
  // Ends the last stage. Then: {"stages": [{"name", "seconds",
  // "cpu_seconds", "skipped"}, ...], "total_seconds"}, the stages in the
  // order they ran.
  nlohmann::ordered_json Finish();

 private:
  struct Entry {
    std::string name;
    double seconds = 0;
    double cpu_seconds = 0;
    bool skipped = false;
  };
  double Now() const;
  // User + system seconds of this process and its waited-for children.
  static double CpuSeconds();
  void EndStage();

  int total_;
  int done_ = 0;
  std::chrono::steady_clock::time_point start_;
  double seconds_before_;
  double stage_start_ = 0;  // Now() when the open stage began
  double stage_cpu_start_ = 0;
  std::vector<Entry> entries_;
  bool open_ = false;
};

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_PIPELINE_STAGE_LOG_H_
