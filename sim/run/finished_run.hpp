// A finished run already in the output folder (DIR/run.h5) is a result. The
// same command again (the same scene text, the same starting state, the same
// dem2d version) has nothing to do; any other run into the folder would
// replace it and leave what was made from it stale, so it is refused unless
// --overwrite, which then names what it leaves stale.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "scene/scene.hpp"

namespace dem2d {

struct FinishedRun {
  bool present = false;  // DIR/run.h5 is a finished dem2d run
  std::string differs;   // "" if it is this scene's run; else what differs, in words
  std::string summary;   // "DIR/run.h5 (scene NAME, step N, t = T s, dem2d VERSION)"
};

// What DIR/run.h5 holds, against the scene about to run with code_version.
FinishedRun finished_run(const std::filesystem::path& run_file, const Scene& scene, const std::string& code_version);

// The files and folders in DIR besides the run's own (run.h5, run.xdmf,
// run.log, .run.lock, .run.work), by name: what replacing the run leaves stale.
std::vector<std::string> beside_the_run(const std::filesystem::path& dir);

// What a run starting afresh in DIR does about a finished run there.
struct Rerun {
  bool nothing_to_do = false;  // DIR/run.h5 is this command's run, and no --overwrite
  std::string finished;        // FinishedRun::summary ("" if there is none)
  std::string replacing;       // with --overwrite: "replacing the finished run ...; ... goes stale, beside it: ..."
};
// Throws OutputDirError (run/output_dir.hpp) if DIR/run.h5 is another
// command's finished run and overwrite is false, naming what differs.
Rerun check_rerun(const std::filesystem::path& dir, const Scene& scene, const std::string& code_version,
                  bool overwrite);

}  // namespace dem2d
