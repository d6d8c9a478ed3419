#include "core/base/iteration_parts.h"

#include <cstdio>

namespace es {

const char* PartName(Part part) {
  static const char* const kNames[] = {
      "render for the fit",  "losses",        "loop texture render + loss",
      "fields (V, D)",       "Euler chain",   "backward (rasterizer)",
      "Adam",                "scene-flow prior", "densification",
      "evaluation",          "checkpoints",   "ranks (wait + allreduce)",
      "other (untimed)"};
  static_assert(sizeof(kNames) / sizeof(kNames[0]) ==
                    static_cast<size_t>(Part::kNumParts),
                "one name per part");
  return kNames[static_cast<int>(part)];
}

Part PartOf(Pass pass, Stage stage) {
  if (pass == Pass::kEvaluation) return Part::kEvaluation;
  if (pass == Pass::kDensify) return Part::kDensification;
  switch (stage) {
    case Stage::kIteration:
    case Stage::kOpticalFlow:
      return Part::kOther;
    case Stage::kProjection:
    case Stage::kBinSort:
    case Stage::kForwardTiles:
    case Stage::kComposition:
      return pass == Pass::kLoopTexture ? Part::kLoopTextureRender
                                        : Part::kFitRender;
    case Stage::kLossL1:
    case Stage::kLossSsim:
    case Stage::kLossBce:
    case Stage::kLossResidual:
    case Stage::kLossEnergy:
      return pass == Pass::kLoopTexture ? Part::kLoopTextureRender
                                        : Part::kLosses;
    case Stage::kBackwardTiles:
    case Stage::kProjectionBackward:
      return Part::kBackward;
    case Stage::kAdam:
      return Part::kAdam;
    case Stage::kDensifyStats:
    case Stage::kDensify:
      return Part::kDensification;
    case Stage::kFieldsForward:
    case Stage::kFieldsBackward:
      return Part::kFields;
    case Stage::kEulerChain:
      return Part::kEulerChain;
    case Stage::kSceneFlow:
      return Part::kFlowPrior;
    case Stage::kEvaluation:
      return Part::kEvaluation;
    case Stage::kCheckpoint:
      return Part::kCheckpoint;
    case Stage::kRankWait:
    case Stage::kAllreduce:
      return Part::kRanks;
    case Stage::kNumStages:
      break;
  }
  return Part::kOther;
}

double PartSeconds(const StageProfile& profile, Part part) {
  int64_t ns = 0;
  for (int p = 0; p < static_cast<int>(Pass::kNumPasses); ++p) {
    for (int s = 0; s < static_cast<int>(Stage::kNumStages); ++s) {
      if (PartOf(Pass(p), Stage(s)) == part)
        ns += profile.nanoseconds(Stage(s), Pass(p));
    }
  }
  return 1e-9 * ns;
}

std::string PartsTable(const StageProfile& profile) {
  const int64_t iterations = profile.calls(Stage::kIteration);
  double total = 0;
  for (int k = 0; k < static_cast<int>(Part::kNumParts); ++k)
    total += PartSeconds(profile, Part(k));
  const double per_it = iterations > 0 ? 1e3 / iterations : 0;
  char line[160];
  std::string out = "profile by part:\n";
  std::snprintf(line, sizeof(line), "%-28s %9s %12s %7s\n", "part", "s",
                "ms/iteration", "%");
  out += line;
  for (int k = 0; k < static_cast<int>(Part::kNumParts); ++k) {
    const double s = PartSeconds(profile, Part(k));
    if (s <= 0) continue;
    std::snprintf(line, sizeof(line), "%-28s %9.2f %12.3f %6.1f%%\n",
                  PartName(Part(k)), s, s * per_it,
                  total > 0 ? 100.0 * s / total : 0.0);
    out += line;
  }
  std::snprintf(line, sizeof(line), "%-28s %9.2f %12.3f %6.1f%%\n", "total",
                total, total * per_it, 100.0);
  out += line;
  int64_t loop_ns = 0;
  for (int s = 0; s < static_cast<int>(Stage::kNumStages); ++s)
    loop_ns += profile.nanoseconds(Stage(s), Pass::kLoopTexture);
  if (loop_ns > 0) {
    std::snprintf(line, sizeof(line),
                  "the loop texture pass in all (its fields, chain and "
                  "backward too): %.2f s, %.3f ms/iteration, %.1f%%\n",
                  1e-9 * loop_ns, 1e-9 * loop_ns * per_it,
                  total > 0 ? 100.0 * 1e-9 * loop_ns / total : 0.0);
    out += line;
  }
  return out;
}

void PrintProfileAndStop(const std::string& title) {
  StageProfile& profile = StageProfile::Get();
  if (!profile.On()) return;
  profile.PrintAndStop(title);
  std::fputs(PartsTable(profile).c_str(), stdout);
  std::fflush(stdout);
}

}  // namespace es
