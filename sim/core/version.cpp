#include "core/version.hpp"

#include "core/share_dir.hpp"

#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>

namespace dem2d {

namespace {

// code_version.txt (written at every build, installed beside data/): a regular file of one short line,
// read at most that far. Anything else (a link to a device, a pipe, a long file) is not read: "".
std::string read_code_version(const std::string& path) {
  constexpr std::size_t kMaxBytes = 256;  // a version and a commit id, with room
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec) || ec) return "";
  std::ifstream in(path, std::ios::binary);
  std::string g(kMaxBytes + 1, '\0');
  in.read(g.data(), static_cast<std::streamsize>(g.size()));
  g.resize(static_cast<std::size_t>(in.gcount()));
  if (g.size() > kMaxBytes || g.find('\0') != std::string::npos) return "";
  g.erase(g.find_last_not_of(" \t\r\n") + 1);  // (an edited file's line end is not part of the version)
  return g.find('\n') == std::string::npos ? g : "";
}

}  // namespace

const std::string& code_version() {
  static const std::string version = [] {
    const std::string g = share_dir().empty() ? "" : read_code_version(share_dir() + "/code_version.txt");
    return std::string(DEM2D_PROJECT_VERSION) + "+" + (g.empty() ? "unknown" : g);
  }();
  return version;
}

}  // namespace dem2d
