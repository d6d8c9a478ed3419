// Tiles a few frames of a scene and their water masks into one PNG, so a
// person can see at a glance what a scene looks like.
//
//   es_contact_sheet --scene DIR --out sheet.png [--count 8]

#include <cstdio>
#include <string>

#include <gflags/gflags.h>
#include <opencv2/imgcodecs.hpp>

#include "apps/common/app_main.h"
#include "core/io/input_error.h"
#include "core/viz/contact_sheet.h"

DEFINE_string(scene, "", "Scene directory (with images/ and masks/).");
DEFINE_string(out, "", "Output PNG file.");
DEFINE_int32(count, 8, "Number of frames, evenly spaced over the video.");

int main(int argc, char** argv) {
  return es::RunApp(
      argc, argv,
      "Tiles frames and their masks into one image.\n"
      "  es_contact_sheet --scene DIR --out sheet.png [--count 8]",
      [] {
        if (FLAGS_scene.empty() || FLAGS_out.empty())
          throw es::InputError("--scene and --out are required");
        const cv::Mat sheet = es::MakeContactSheet(FLAGS_scene, FLAGS_count);
        if (!cv::imwrite(FLAGS_out, sheet))
          throw es::InputError(FLAGS_out + ": cannot write image");
        std::printf("wrote %s (%dx%d)\n", FLAGS_out.c_str(), sheet.cols,
                    sheet.rows);
        return 0;
      });
}
