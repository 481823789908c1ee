#include "core/version.hpp"

#include "core/share_dir.hpp"

#include <fstream>
#include <sstream>

namespace dem2d {

const std::string& code_version() {
  static const std::string version = [] {
    std::ostringstream git;  // code_version.txt: written at every build, installed beside data/
    if (std::ifstream in(share_dir() + "/code_version.txt"); !share_dir().empty() && in) git << in.rdbuf();
    const std::string g = git.str();
    return std::string(DEM2D_PROJECT_VERSION) + "+" + (g.empty() ? "unknown" : g);
  }();
  return version;
}

}  // namespace dem2d
