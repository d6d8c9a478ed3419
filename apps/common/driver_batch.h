#ifndef EULERSPLAT_APPS_COMMON_DRIVER_BATCH_H_
#define EULERSPLAT_APPS_COMMON_DRIVER_BATCH_H_

// eulersplat --scenes: a batch of scenes, each run by the driver on a group
// of the batch's ranks, the groups side by side. Each scene's run is an
// eulersplat of its own (--scene S --out OUT/<name> --ranks <its group's>),
// its output in OUT/<name>.log; a scene that fails is reported and the
// others go on.

#include <string>
#include <vector>

namespace es {

struct SceneBatchOptions {
  std::vector<std::string> scenes;  // scene directories
  std::string out;                  // OUT/<scene's folder name> per scene
  int ranks = 1;                    // of the whole batch
  int groups = 0;                   // 0: min(scenes, ranks)
  int threads = 1;                  // CPU threads of the whole batch
  std::string self;                 // the eulersplat binary
  // Flags every scene's run gets as well (--preset, iterations, ...).
  std::vector<std::string> flags;
};

// --scenes' value: directories separated by commas, or the path of a text
// file that lists one per line (blank lines and lines from '#' ignored).
std::vector<std::string> ParseSceneList(const std::string& value);

// Ranks per group: `ranks` shared by `groups` as evenly as can be, the
// first groups one more where they do not divide.
std::vector<int> GroupRanks(int ranks, int groups);

// A scene's output folder name: its directory's last component.
std::string SceneName(const std::string& dir);

// Checks the batch before any work (InputError): scenes given, each a
// directory, their names distinct, 1 <= groups <= ranks (with 0 resolved
// to min(scenes, ranks)). Returns the options with groups resolved.
SceneBatchOptions CheckSceneBatch(SceneBatchOptions options);

// Runs every scene (the next in line starts when a group is free),
// printing a line when each starts and ends and its run's stage lines
// ("[eulersplat] ...") prefixed with its name. Returns how many failed.
int RunSceneBatch(const SceneBatchOptions& options);

}  // namespace es

#endif  // EULERSPLAT_APPS_COMMON_DRIVER_BATCH_H_
