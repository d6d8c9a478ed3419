#ifndef EULERSPLAT_CORE_IO_IMAGE_WRITE_H_
#define EULERSPLAT_CORE_IO_IMAGE_WRITE_H_

#include <string>

#include <opencv2/core.hpp>

namespace es {

// Encodes `image` by the extension of `path` (png, jpg) and writes it
// atomically (core/io/atomic_file.h). Throws InputError naming `path` when
// it cannot be encoded or written.
void WriteImageAtomically(const std::string& path, const cv::Mat& image);

}  // namespace es

#endif  // EULERSPLAT_CORE_IO_IMAGE_WRITE_H_
