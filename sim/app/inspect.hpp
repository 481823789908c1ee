// `dem2d inspect RUN.h5`: reads a whole run file through the analyses' reader
// (runfile/run_reader.hpp), every snapshot, contact and series row and the
// parameters, with all its checks, and prints what the file holds. The
// Python reader's check_run (python/dem2d) applies the same rules; make fuzz
// compares their verdicts on damaged files.
#pragma once

#include <string>

namespace dem2d {

// 0: a sound run file (its summary on stdout); 2: damaged or not a run file
// (the message, naming the file and the dataset, on stderr).
int inspect_run_file(const std::string& path);

}  // namespace dem2d
