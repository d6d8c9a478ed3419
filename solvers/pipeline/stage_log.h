#ifndef EULERSPLAT_SOLVERS_PIPELINE_STAGE_LOG_H_
#define EULERSPLAT_SOLVERS_PIPELINE_STAGE_LOG_H_

#include <chrono>
#include <string>

namespace es {

// Numbers the driver's stages "k/N" and says how long the run has taken,
// so a person sees where a long run stands.
class StageLog {
 public:
  explicit StageLog(int total);

  // Prints "[eulersplat] stage k/N: name (S s so far)".
  void Begin(const std::string& name);

 private:
  int total_;
  int done_ = 0;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_PIPELINE_STAGE_LOG_H_
