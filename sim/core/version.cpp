#include "core/version.hpp"

#include "core/share_dir.hpp"

#include <fstream>
#include <sstream>

namespace dem2d {

const std::string& code_version() {
  static const std::string version = [] {
    std::ostringstream git;  // code_version.txt: written at every build, installed beside data/
    if (std::ifstream in(share_dir() + "/code_version.txt"); !share_dir().empty() && in) git << in.rdbuf();
    std::string g = git.str();
    g.erase(g.find_last_not_of(" \t\r\n") + 1);  // (an edited file's line end is not part of the version)
    return std::string(DEM2D_PROJECT_VERSION) + "+" + (g.empty() ? "unknown" : g);
  }();
  return version;
}

}  // namespace dem2d
