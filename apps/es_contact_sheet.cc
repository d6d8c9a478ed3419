// Tiles a few frames of a scene and their water masks into one PNG, so a
// person can see at a glance what a scene looks like.
//
//   es_contact_sheet --scene DIR --out sheet.png [--count 8]

#include <cstdio>
#include <string>

#include <gflags/gflags.h>
#include <opencv2/core.hpp>

#include "apps/common/app_main.h"
#include "apps/common/flag_checks.h"
#include "core/io/image_file.h"
#include "core/base/input_error.h"
#include "core/viz/contact_sheet.h"

constexpr char kUsage[] =
    "Tiles frames and their masks into one image.\n"
    "  es_contact_sheet --scene DIR --out sheet.png [--count 8]";

DEFINE_string(scene, "", "Scene directory (with images/ and masks/).");
DEFINE_string(out, "", "Output PNG file.");
DEFINE_int32(count, 8, "Number of frames, evenly spaced over the video.");

int main(int argc, char** argv) {
  return es::RunApp(argc, argv, kUsage, [] {
    es::RequireFlag("scene", FLAGS_scene);
    es::RequireFlag("out", FLAGS_out);
    es::RequireAtLeast("count", FLAGS_count, 1);
    const cv::Mat sheet = es::MakeContactSheet(FLAGS_scene, FLAGS_count);
    es::WriteImageAtomically(FLAGS_out, sheet);
    std::printf("wrote %s (%dx%d)\n", FLAGS_out.c_str(), sheet.cols,
                sheet.rows);
    return 0;
  });
}
