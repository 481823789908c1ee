#include "run/finished_run.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/number_text.hpp"
#include "run/output_dir.hpp"
#include "runfile/h5.hpp"
#include "runfile/run_format.hpp"

namespace dem2d {

namespace fs = std::filesystem;

namespace {

struct FinishedRun {
  bool present = false;  // DIR/run.h5 is a finished dem2d run
  std::string differs;   // "" if it is this scene's run; else what differs, in words
  std::string summary;   // "DIR/run.h5 (step N, t = T s, dem2d VERSION)"
};

// What DIR/run.h5 holds, against the scene about to run with code_version.
FinishedRun finished_run(const fs::path& run_file, const Scene& scene, const std::string& code_version) {
  FinishedRun r;
  std::error_code ec;
  if (!fs::exists(run_file, ec)) return r;
  try {
    const h5::File f = h5::File::open_read(run_file.string());
    if (!h5::has_attr(f, "/", "format") || !h5::read_attr_string(f, "/", "format").starts_with("dem2d-run"))
      return r;  // not a run file: OutputDir's to refuse
    r.present = true;
    const auto text = [&](const char* name) {
      return h5::has_attr(f, "/", name) ? h5::read_attr_string(f, "/", name) : std::string("(none)");
    };
    const std::string version = text("code_version");
    const double end = std::round(h5::read_attr_double(f, "/", "end_time") * 1e6) / 1e6;  // (s), to the microsecond
    r.summary = run_file.string() + " (step " + std::to_string(h5::read_attr_int(f, "/", "steps")) + ", t = " +
                shortest(end) + " s, dem2d " + version + ")";
    std::vector<std::string> what;
    if (h5::read_attr_string(f, "/", "format") != kRunFileFormat)
      what.push_back("its format is " + h5::read_attr_string(f, "/", "format") + ", this dem2d writes " +
                     kRunFileFormat);
    if (text("scene_text") != scene.text) what.push_back("it ran another scene or other overlays");
    if (text("initial_digest") != (scene.initial_run.empty() ? "" : scene.initial_digest))
      what.push_back("it started from another state: the initial run is another one, or was made again");
    if (version != code_version) what.push_back("it was made by dem2d " + version + ", this is " + code_version);
    for (std::size_t k = 0; k < what.size(); ++k) r.differs += (k ? "; " : "") + what[k];
  } catch (const std::exception& e) {
    r.present = true;
    r.differs = std::string("it cannot be read: ") + e.what();
    r.summary = run_file.string();
  }
  return r;
}

// The files and folders in DIR besides the run's own, by name: what replacing the run leaves stale.
std::vector<std::string> beside_the_run(const fs::path& dir) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    if (name != "run.h5" && name != "run.xdmf" && name != "run.log" && name != ".run.lock" && name != ".run.work")
      names.push_back(name);
  }
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace

Rerun check_rerun(const fs::path& dir, const Scene& scene, const std::string& code_version, bool overwrite) {
  const FinishedRun done = finished_run(dir / "run.h5", scene, code_version);
  Rerun r;
  r.finished = done.summary;
  if (!done.present) return r;
  if (!overwrite) {
    if (!done.differs.empty())
      throw OutputDirError(done.summary + " is a finished run, not of this command: " + done.differs +
                           ". Pass --overwrite to replace it (what was made from it becomes stale), or give "
                           "another --out");
    r.nothing_to_do = true;
    return r;
  }
  r.replacing = "replacing the finished run " + done.summary + ": " +
                (done.differs.empty() ? std::string("the same run, made again") : done.differs) +
                "; what was made from it goes stale";
  const std::vector<std::string> stale = beside_the_run(dir);
  constexpr std::size_t kNamed = 12;
  for (std::size_t k = 0; k < stale.size() && k < kNamed; ++k) r.replacing += (k ? ", " : ", beside it: ") + stale[k];
  if (stale.size() > kNamed) r.replacing += " and " + std::to_string(stale.size() - kNamed) + " more";
  return r;
}

}  // namespace dem2d
