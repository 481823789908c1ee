// The folder a run writes into (--out DIR). The run holds it (a lock that a
// second run into DIR reports by its pid) and never deletes or replaces a
// file it did not make, nor writes through a symbolic link:
//   DIR/run.h5, DIR/run.xdmf  replaced only if they are a dem2d run's (or --overwrite)
//   DIR/run.log               appended (a dem2d run's log across resumes)
//   DIR/.run.work/            its segments, checkpoint and the run file being assembled;
//                             removed only if it holds nothing else
//   DIR/.run.lock             the lock (left in place: empty of meaning when no run holds it)
// and a run is refused an --out that holds the run it starts from (--initial).
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>

namespace dem2d {

// A folder the run may not write into: the message names the file and what to do.
struct OutputDirError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

class OutputDir {
 public:
  // Checks DIR and takes its lock before anything is written; throws OutputDirError.
  OutputDir(const std::string& dir, const std::string& initial_run, bool overwrite);
  ~OutputDir();
  OutputDir(const OutputDir&) = delete;
  OutputDir& operator=(const OutputDir&) = delete;

  const std::filesystem::path& path() const { return dir_; }
  std::filesystem::path work() const { return dir_ / ".run.work"; }
  // An empty working folder for a fresh run (an earlier unfinished run's removed, if it is dem2d's).
  void fresh_work() const;
  // Removes the working folder: only the files dem2d makes there; OutputDirError if it holds others.
  void remove_work() const;

 private:
  std::filesystem::path dir_;
  int lock_fd_ = -1;
};

}  // namespace dem2d
