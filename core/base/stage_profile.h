#ifndef EULERSPLAT_CORE_BASE_STAGE_PROFILE_H_
#define EULERSPLAT_CORE_BASE_STAGE_PROFILE_H_

// Where a training iteration's wall time goes, per stage (the trainers'
// --profile). A ScopedStage costs one relaxed atomic load when profiling is
// off. Scopes nest: each stage is charged its own time without the stages
// opened inside it, and what an iteration spends outside every stage shows
// as "other". Scopes opened inside OpenMP parallel regions are ignored, so
// the figures are wall time. A ScopedPass says which pass of an iteration
// the stages belong to (the fit, the loop's second render, densification,
// an evaluation), so the same rasterizer stages can be told apart by what
// they rendered for (core/base/iteration_parts.h groups them).

#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <string>

#include <omp.h>

namespace es {

enum class Stage : int {
  kIteration = 0,  // one trainer step; its untimed remainder is "other"
  kProjection,
  kBinSort,
  kForwardTiles,
  kBackwardTiles,
  kProjectionBackward,
  kLossL1,
  kLossSsim,
  kLossBce,
  kLossResidual,
  kLossEnergy,
  kAdam,
  kDensifyStats,
  kDensify,
  kFieldsForward,
  kFieldsBackward,
  kEulerChain,
  kComposition,
  kSceneFlow,
  kOpticalFlow,
  kRankWait,    // --profile with ranks: waiting for the slowest rank
  kAllreduce,   // summing a batch's gradients over the ranks
  kEvaluation,  // held-out evaluation between iterations, untimed remainder
  kCheckpoint,  // writing checkpoints and the training history
  kNumStages
};

// What a stage's time was spent for.
enum class Pass : int {
  kFit = 0,      // the iteration's render(s) fitting the frame(s)
  kLoopTexture,  // the loop's second render, for its texture loss
  kDensify,      // densification, its own renders included
  kEvaluation,   // held-out evaluation
  kNumPasses
};

inline const char* StageName(Stage s) {
  static const char* const kNames[] = {
      "other (untimed)",    "projection",          "binning + sort",
      "forward tiles",      "backward tiles",      "projection backward",
      "loss: L1",           "loss: SSIM",          "loss: mask BCE",
      "loss: residual",     "loss: water energy",  "Adam",
      "densification stats", "densify + prune",    "fields forward",
      "fields backward",    "Euler chain",         "composition",
      "scene-flow loss",    "optical flow + lifting", "waiting for ranks",
      "allreduce",          "held-out evaluation", "checkpoint + history"};
  static_assert(sizeof(kNames) / sizeof(kNames[0]) ==
                    static_cast<size_t>(Stage::kNumStages),
                "one name per stage");
  return kNames[static_cast<int>(s)];
}

class StageProfile {
 public:
  static StageProfile& Get() {
    static StageProfile profile;
    return profile;
  }
  static bool On() { return Get().on_.load(std::memory_order_relaxed); }

  void Enable(bool on) { on_.store(on, std::memory_order_relaxed); }
  void Reset() {
    for (auto& pass : ns_)
      for (auto& n : pass) n.store(0, std::memory_order_relaxed);
    for (auto& pass : calls_)
      for (auto& c : pass) c.store(0, std::memory_order_relaxed);
    pass_.store(static_cast<int>(Pass::kFit), std::memory_order_relaxed);
  }
  // Charges `ns` to stage `s` in the current pass.
  void Add(Stage s, int64_t ns) {
    const int p = pass_.load(std::memory_order_relaxed);
    ns_[p][static_cast<int>(s)].fetch_add(ns, std::memory_order_relaxed);
    calls_[p][static_cast<int>(s)].fetch_add(1, std::memory_order_relaxed);
  }
  // Over every pass.
  int64_t nanoseconds(Stage s) const {
    int64_t sum = 0;
    for (int p = 0; p < kPasses; ++p) sum += nanoseconds(s, Pass(p));
    return sum;
  }
  int64_t calls(Stage s) const {
    int64_t sum = 0;
    for (int p = 0; p < kPasses; ++p)
      sum += calls_[p][static_cast<int>(s)].load(std::memory_order_relaxed);
    return sum;
  }
  int64_t nanoseconds(Stage s, Pass p) const {
    return ns_[static_cast<int>(p)][static_cast<int>(s)].load(
        std::memory_order_relaxed);
  }

  Pass pass() const { return Pass(pass_.load(std::memory_order_relaxed)); }
  void set_pass(Pass p) {
    pass_.store(static_cast<int>(p), std::memory_order_relaxed);
  }

  // Starts a profile from zero when `on`.
  void Start(bool on) {
    Reset();
    Enable(on);
  }
  // Prints the table to stdout (if on) and stops profiling, so that work
  // after the training loop (evaluation, writing) is not counted.
  void PrintAndStop(const std::string& title) {
    if (!On()) return;
    Enable(false);
    std::fputs(Table(title).c_str(), stdout);
    std::fflush(stdout);
  }

  // Per-stage table: ms per iteration and share of the iteration time, then
  // the stages that ran outside iterations (setup such as optical flow) in
  // total ms.
  std::string Table(const std::string& title) const {
    const int64_t iterations = calls(Stage::kIteration);
    int64_t total = 0;
    for (int s = 0; s < static_cast<int>(Stage::kNumStages); ++s)
      total += nanoseconds(static_cast<Stage>(s));
    char line[160];
    std::string out = "profile: " + title + "\n";
    std::snprintf(line, sizeof(line), "%-24s %10s %12s %7s\n", "stage",
                  "calls", "ms/iteration", "%");
    out += line;
    const double per_it = iterations > 0 ? 1e-6 / iterations : 1e-6;
    for (int s = 1; s <= static_cast<int>(Stage::kNumStages); ++s) {
      // "other" last.
      const Stage stage =
          static_cast<Stage>(s % static_cast<int>(Stage::kNumStages));
      const int64_t ns = nanoseconds(stage);
      if (calls(stage) == 0) continue;
      std::snprintf(line, sizeof(line), "%-24s %10lld %12.3f %6.1f%%\n",
                    StageName(stage), static_cast<long long>(calls(stage)),
                    ns * per_it, total > 0 ? 100.0 * ns / total : 0.0);
      out += line;
    }
    std::snprintf(line, sizeof(line),
                  "%-24s %10lld %12.3f %6.1f%%\n", "total",
                  static_cast<long long>(iterations), total * per_it, 100.0);
    out += line;
    return out;
  }

 private:
  static constexpr int kPasses = static_cast<int>(Pass::kNumPasses);
  static constexpr int kStages = static_cast<int>(Stage::kNumStages);
  StageProfile() { Reset(); }
  std::atomic<bool> on_{false};
  std::atomic<int> pass_{0};
  std::atomic<int64_t> ns_[kPasses][kStages];
  std::atomic<int64_t> calls_[kPasses][kStages];
};

// Charges the stages timed in its scope to `pass`; the pass before it
// again afterwards. Costs one relaxed load when profiling is off.
class ScopedPass {
 public:
  explicit ScopedPass(Pass pass) {
    if (!StageProfile::On() || omp_in_parallel()) return;
    on_ = true;
    previous_ = StageProfile::Get().pass();
    StageProfile::Get().set_pass(pass);
  }
  ~ScopedPass() {
    if (on_) StageProfile::Get().set_pass(previous_);
  }
  ScopedPass(const ScopedPass&) = delete;
  ScopedPass& operator=(const ScopedPass&) = delete;

 private:
  bool on_ = false;
  Pass previous_ = Pass::kFit;
};

class ScopedStage {
 public:
  // `active` false skips the timer (for calls too small to time alone).
  explicit ScopedStage(Stage stage, bool active = true) : stage_(stage) {
    // Inside a parallel region several threads would add up CPU time.
    if (!active || !StageProfile::On() || omp_in_parallel()) return;
    on_ = true;
    parent_ = Current();
    Current() = this;
    start_ = Clock::now();
  }
  ~ScopedStage() {
    if (!on_) return;
    const int64_t elapsed =
        std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() -
                                                             start_)
            .count();
    StageProfile::Get().Add(stage_, elapsed - children_);
    if (parent_) parent_->children_ += elapsed;
    Current() = parent_;
  }
  ScopedStage(const ScopedStage&) = delete;
  ScopedStage& operator=(const ScopedStage&) = delete;

 private:
  using Clock = std::chrono::steady_clock;
  static ScopedStage*& Current() {
    thread_local ScopedStage* current = nullptr;
    return current;
  }
  Stage stage_;
  bool on_ = false;
  ScopedStage* parent_ = nullptr;
  int64_t children_ = 0;
  Clock::time_point start_;
};

}  // namespace es

#endif  // EULERSPLAT_CORE_BASE_STAGE_PROFILE_H_
