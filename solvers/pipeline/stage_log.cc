#include "solvers/pipeline/stage_log.h"

#include <sys/resource.h>

#include <cstdio>

namespace es {

StageLog::StageLog(int total, double seconds_before)
    : total_(total),
      start_(std::chrono::steady_clock::now()),
      seconds_before_(seconds_before) {
  entries_.push_back(
      {"frames, poses and masks", seconds_before, CpuSeconds(), false});
}

double StageLog::CpuSeconds() {
  double seconds = 0;
  for (int who : {RUSAGE_SELF, RUSAGE_CHILDREN}) {
    rusage usage{};
    if (getrusage(who, &usage) != 0) continue;
    for (const timeval& t : {usage.ru_utime, usage.ru_stime})
      seconds += t.tv_sec + 1e-6 * t.tv_usec;
  }
  return seconds;
}

double StageLog::Now() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() -
                                       start_)
      .count();
}

void StageLog::EndStage() {
  if (!open_) return;
  entries_.back().seconds = Now() - stage_start_;
  entries_.back().cpu_seconds = CpuSeconds() - stage_cpu_start_;
  open_ = false;
}

void StageLog::Begin(const std::string& name) {
  EndStage();
  stage_start_ = Now();
  stage_cpu_start_ = CpuSeconds();
  entries_.push_back({name, 0, 0, false});
  open_ = true;
  std::printf("\n[eulersplat] stage %d/%d: %s (%.0f s so far)\n", ++done_,
              total_, name.c_str(), seconds_before_ + stage_start_);
  std::fflush(stdout);
}

void StageLog::Skipped() {
  if (open_) entries_.back().skipped = true;
}

nlohmann::ordered_json StageLog::Finish() {
  EndStage();
  nlohmann::ordered_json stages = nlohmann::ordered_json::array();
  for (const Entry& e : entries_) {
    stages.push_back({{"name", e.name},
                      {"seconds", e.seconds},
                      {"cpu_seconds", e.cpu_seconds},
                      {"skipped", e.skipped}});
  }
  return {{"stages", stages}, {"total_seconds", seconds_before_ + Now()}};
}

}  // namespace es
