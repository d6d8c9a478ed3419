#include "core/io/image_file.h"

#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <vector>

#include "core/base/atomic_file.h"
#include "core/base/input_error.h"

namespace es {

void WriteImageAtomically(const std::string& path, const cv::Mat& image) {
  std::vector<uchar> bytes;
  bool ok = false;
  try {
    ok = cv::imencode(std::filesystem::path(path).extension().string(), image,
                      bytes);
  } catch (const cv::Exception&) {
  }
  if (!ok) throw InputError(path + ": cannot encode the image");
  WriteFileAtomically(path, [&](std::ofstream& out) {
    out.write(reinterpret_cast<const char*>(bytes.data()),
              static_cast<std::streamsize>(bytes.size()));
  });
}

}  // namespace es
