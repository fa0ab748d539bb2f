#include "aar/data_path.h"

namespace aar {

std::filesystem::path DataRoot() {
  static const std::filesystem::path root = [] {
    std::error_code ec;
    const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (!ec) {
      const std::filesystem::path installed = exe.parent_path().parent_path() / "share" / "aar";
      if (std::filesystem::is_directory(installed / "scenes", ec)) return installed;
    }
    return std::filesystem::path(AAR_SOURCE_DIR);
  }();
  return root;
}

std::filesystem::path DataFile(const std::string& relative) { return DataRoot() / relative; }

}  // namespace aar
