#include "core/share_dir.hpp"

#include <cstdlib>
#include <filesystem>
#include <system_error>

namespace dem2d {
namespace {

namespace fs = std::filesystem;

struct Share {
  std::string dir;       // share/dem2d, or "" if it is not where it belongs
  std::string expected;  // where it belongs, for the message
  std::string program;
  bool from_env = false;  // DEM2D_SHARE named it
};

// Only where this project puts share/dem2d, never a parent's or the current
// folder's (another installation's data and version would be taken):
//   a build tree (the program's folder or its parent is the tree, holding
//   CMakeCache.txt): TREE/share/dem2d;
//   an installation: PREFIX/bin/<program> and PREFIX/libexec/dem2d/<program>:
//   PREFIX/share/dem2d.
const Share& share() {
  static const Share s = [] {
    Share r;
    std::error_code ec;
    if (const char* env = std::getenv("DEM2D_SHARE"); env && *env) {
      r.expected = env;
      r.from_env = true;
      if (fs::is_directory(fs::path(env) / "data", ec)) r.dir = env;  // (else the error names the variable)
      return r;
    }
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (ec) {
      r.expected = "(the program's own folder is unknown: /proc/self/exe)";
      return r;
    }
    r.program = exe.string();
    const fs::path bin = exe.parent_path();
    fs::path root = bin.parent_path();                                          // PREFIX/bin, TREE/sim
    if (fs::exists(bin.parent_path().parent_path() / "CMakeCache.txt", ec))     // TREE/analysis/<x>.build
      root = bin.parent_path().parent_path();
    else if (!fs::exists(root / "CMakeCache.txt", ec) && bin.filename() == "dem2d")  // PREFIX/libexec/dem2d
      root = root.parent_path();
    const fs::path dir = root / "share" / "dem2d";
    r.expected = dir.string();
    if (fs::is_directory(dir / "data", ec)) r.dir = dir.string();
    return r;
  }();
  return s;
}

}  // namespace

const std::string& share_dir() { return share().dir; }

std::string share_problem() {
  const Share& s = share();
  if (!s.dir.empty()) return "";
  if (s.from_env)
    return "DEM2D_SHARE=" + s.expected + " holds no data/ folder: set it to a share/dem2d folder of an "
           "installation (the one holding data/ and code_version.txt), or unset it";
  return (s.program.empty() ? std::string("this program") : s.program) + ": its data are missing: no " + s.expected +
         "/data, where its installation (make install) or build tree keeps them; install it again, or set "
         "DEM2D_SHARE to a share/dem2d folder to use that one";
}

std::string data_file(const std::string& relative) {
  return share().expected + "/data/" + relative;  // (where it belongs: an error opening it names that place)
}

}  // namespace dem2d
