#ifndef EULERSPLAT_CORE_IO_IMAGE_FILE_H_
#define EULERSPLAT_CORE_IO_IMAGE_FILE_H_

#include <opencv2/core.hpp>
#include <string>

namespace es {

// Encodes `image` in the format of `path`'s extension (.png, .jpg, ...) and
// writes it atomically (atomic_file.h). Throws InputError naming `path` if
// it cannot be encoded or written.
void WriteImageAtomically(const std::string& path, const cv::Mat& image);

}  // namespace es

#endif  // EULERSPLAT_CORE_IO_IMAGE_FILE_H_
