#include "core/share_dir.hpp"

#include <cstdlib>
#include <filesystem>
#include <system_error>

namespace dem2d {

const std::string& share_dir() {
  static const std::string dir = [] {
    namespace fs = std::filesystem;
    if (const char* env = std::getenv("DEM2D_SHARE"); env && *env) return std::string(env);
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (ec) return std::string();
    for (fs::path d = exe.parent_path(); !d.empty(); d = d.parent_path()) {
      const fs::path share = d / "share" / "dem2d";
      if (fs::is_directory(share / "data", ec)) return share.string();
      if (d == d.root_path()) break;
    }
    return std::string();
  }();
  return dir;
}

std::string data_file(const std::string& relative) {
  const std::string& share = share_dir();
  return (share.empty() ? std::string("share/dem2d") : share) + "/data/" + relative;
}

}  // namespace dem2d
