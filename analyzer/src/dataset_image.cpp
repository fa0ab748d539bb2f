#include "aar/analyzer/dataset_image.h"

#include "aar/error.h"
#include "aar/png_check.h"

namespace aar {

cv::Mat ReadListedImage(const std::filesystem::path& dataset, const Manifest& manifest, const FileRef& ref, int flags,
                        const std::string& what) {
  const std::string path = (dataset / ref.path).string();
  const std::string bytes = ReadListedFile(dataset, manifest, ref);
  CheckPngStructure(bytes, path);
  cv::Mat image =
      cv::imdecode(cv::Mat(1, static_cast<int>(bytes.size()), CV_8U, const_cast<char*>(bytes.data())), flags);
  if (image.empty()) throw Error(path + ": cannot decode " + what);
  return image;
}

}  // namespace aar
