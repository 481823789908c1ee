// A finished run already in the output folder (DIR/run.h5) is a result. The
// same command again (the same scene text, the same starting state, the same
// dem2d version) has nothing to do; any other run into the folder would
// replace it and leave what was made from it stale, so it is refused unless
// --overwrite, which then names what it leaves stale.
#pragma once

#include <filesystem>
#include <string>

#include "scene/scene.hpp"

namespace dem2d {

// What a run starting afresh in DIR does about a finished run there.
struct Rerun {
  bool nothing_to_do = false;  // DIR/run.h5 is this command's run, and no --overwrite
  std::string finished;        // "DIR/run.h5 (step N, t = T s, dem2d VERSION)" ("" if there is none)
  std::string replacing;       // with --overwrite: "replacing the finished run ...; ... goes stale, beside it: ..."
};
// Throws OutputDirError (run/output_dir.hpp) if DIR/run.h5 is another
// command's finished run and overwrite is false, naming what differs.
Rerun check_rerun(const std::filesystem::path& dir, const Scene& scene, const std::string& code_version,
                  bool overwrite);

}  // namespace dem2d
