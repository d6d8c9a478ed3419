#ifndef EULERSPLAT_SOLVERS_PIPELINE_RUN_SHEET_H_
#define EULERSPLAT_SOLVERS_PIPELINE_RUN_SHEET_H_

#include <filesystem>

namespace es {

// OUT/contact_sheet.png, what a driver run produced at a glance: four
// frames over one loop of the fixed-view animation (OUT/animate_fixed) and
// of the tracks video (OUT/animate), four per row, each labelled, and below
// them the training plots (OUT/plots). The frames are enlarged to the
// plots' width. Writes nothing when none of these exist.
void WriteRunContactSheet(const std::filesystem::path& out, int cycle_length);

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_PIPELINE_RUN_SHEET_H_
