#include "core/io/image_write.h"

#include <filesystem>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "core/io/atomic_file.h"
#include "core/io/input_error.h"

namespace es {

void WriteImageAtomically(const std::string& path, const cv::Mat& image) {
  std::vector<uchar> bytes;
  const std::string ext = std::filesystem::path(path).extension().string();
  bool ok = false;
  try {
    ok = cv::imencode(ext, image, bytes);
  } catch (const cv::Exception&) {
    ok = false;
  }
  if (!ok) throw InputError(path + ": cannot encode the image as " + ext);
  WriteFileAtomically(path, [&bytes](std::ofstream& out) {
    out.write(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  });
}

}  // namespace es
