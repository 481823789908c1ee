#include "run/output_dir.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <regex>

#include "runfile/h5.hpp"

namespace dem2d {

namespace fs = std::filesystem;

namespace {

// What dem2d makes in DIR/.run.work: segments (and their temporaries), the checkpoint, the run file being assembled.
bool made_by_dem2d(const fs::path& entry) {
  static const std::regex known(R"((segment_\d{6}\.h5|checkpoint\.h5|run\.(h5|xdmf)\.partial)(\.tmp)?)");
  return std::regex_match(entry.filename().string(), known);
}

// A dem2d run file: HDF5 whose format attribute names one.
bool is_run_file(const fs::path& p) {
  try {
    return h5::read_attr_string(h5::File::open_read(p.string()), "/", "format").starts_with("dem2d-run");
  } catch (const std::exception&) {
    return false;
  }
}

// A dem2d run's XDMF: it points into its run.h5.
bool is_run_xdmf(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::string head(65536, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  return head.find("<Xdmf") != std::string::npos && head.find("run.h5:/") != std::string::npos;
}

// `p` is `dir` or lies (through any links) below it.
bool inside(const fs::path& p, const fs::path& dir) {
  std::error_code ec;
  const fs::path a = fs::weakly_canonical(p, ec), b = fs::weakly_canonical(dir, ec);
  if (ec) return false;
  const auto [end, _] = std::mismatch(b.begin(), b.end(), a.begin(), a.end());
  return end == b.end();
}

}  // namespace

OutputDir::OutputDir(const std::string& dir, const std::string& initial_run, bool overwrite) : dir_(dir) {
  std::error_code ec;
  if (fs::exists(dir_, ec) && !fs::is_directory(dir_, ec))
    throw OutputDirError("--out " + dir + ": not a folder");
  fs::create_directories(dir_);
  const fs::path run = dir_ / "run.h5";
  // anywhere inside it, not only its run.h5: the run's work folder and its run.h5 are replaced or deleted
  // (or its run.h5 under another name: a hard link)
  const bool holds_initial =
      !initial_run.empty() && (inside(initial_run, dir_) || (fs::exists(run, ec) && fs::equivalent(initial_run, run, ec)));
  if (holds_initial)
    throw OutputDirError("--out " + dir + " holds the run this one starts from (--initial " + initial_run +
                         "): a run replaces and deletes files in its --out; give another --out");
  for (const std::string name : {"run.h5", "run.xdmf", "run.log", ".run.work", ".run.lock"}) {
    const fs::path p = dir_ / name;
    if (fs::is_symlink(p, ec))
      throw OutputDirError(p.string() + " is a symbolic link: dem2d does not write through one it "
                           "did not make; remove it or give another --out");
    // what the run writes there: a pipe would block it, a folder lose its log
    const fs::file_status st = fs::symlink_status(p, ec);
    const bool folder = name == ".run.work";
    if (fs::exists(st) && (folder ? !fs::is_directory(st) : !fs::is_regular_file(st)))
      throw OutputDirError(p.string() + " is " +
                           (fs::is_directory(st) ? "a folder" : fs::is_fifo(st) ? "a pipe" : "not a regular file") +
                           ": dem2d writes its " + (folder ? "work folder" : "own file") +
                           " there; remove it or give another --out");
  }
  lock_fd_ = ::open((dir_ / ".run.lock").c_str(), O_RDWR | O_CREAT | O_NOFOLLOW | O_CLOEXEC, 0644);
  if (lock_fd_ < 0)
    throw OutputDirError((dir_ / ".run.lock").string() + ": cannot open the folder's lock: " + std::strerror(errno));
  if (::flock(lock_fd_, LOCK_EX | LOCK_NB) != 0) {
    char pid[32] = {};
    const ssize_t got = ::pread(lock_fd_, pid, sizeof pid - 1, 0);
    ::close(lock_fd_);
    lock_fd_ = -1;
    throw OutputDirError("--out " + dir + ": another dem2d run" +
                         (got > 0 ? " (pid " + std::string(pid, static_cast<std::size_t>(got)) + ")" : "") +
                         " is writing into this folder; wait for it to end, or give another --out");
  }
  const std::string me = std::to_string(::getpid());  // for a second run's message only: failing to write it is harmless
  if (::ftruncate(lock_fd_, 0) == 0) (void)!::pwrite(lock_fd_, me.data(), me.size(), 0);
  if (!overwrite) {
    if (fs::exists(run, ec) && !is_run_file(run))
      throw OutputDirError(run.string() + " is not a dem2d run file: dem2d does not replace a file it did not "
                           "make; move it, give another --out, or pass --overwrite");
    const fs::path xdmf = dir_ / "run.xdmf";
    if (fs::exists(xdmf, ec) && !is_run_xdmf(xdmf))
      throw OutputDirError(xdmf.string() + " is not a dem2d run's XDMF: dem2d does not replace a file it did not "
                           "make; move it, give another --out, or pass --overwrite");
  }
}

OutputDir::~OutputDir() {
  if (lock_fd_ >= 0) ::close(lock_fd_);  // (releases the lock)
}

void OutputDir::fresh_work() const {
  remove_work();
  fs::create_directories(work());
}

void OutputDir::remove_work() const {
  const fs::path w = work();
  std::error_code ec;
  if (!fs::exists(w, ec)) return;
  if (!fs::is_directory(w, ec)) throw OutputDirError(w.string() + " is not dem2d's working folder; move it");
  for (const fs::directory_entry& e : fs::directory_iterator(w))
    if (!e.is_regular_file() || e.is_symlink() || !made_by_dem2d(e.path()))
      throw OutputDirError(w.string() + " holds " + e.path().filename().string() +
                           ", which dem2d did not make: move it out (dem2d removes only its own files there)");
  for (const fs::directory_entry& e : fs::directory_iterator(w)) fs::remove(e.path());
  fs::remove(w);
}

}  // namespace dem2d
