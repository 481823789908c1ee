// The command line every analysis stage shares (docs/stages.md):
//   <stage> RUN.h5 --out OUT [--config FILE] [--study FILE] [its own options] [--version]
// and its exit codes: 0 done; 1 an output could not be written; 2 bad input
// (run, config, study or events file, command line). Messages start with the
// stage's name; the last line says what was measured and where it went.
// (The parser, CLI11, is compiled once, in stage_main.cpp.)
#pragma once

#include <cstdio>
#include <exception>
#include <memory>
#include <new>
#include <string>

namespace dem2d::analysis {

class StageCommand {
 public:
  static constexpr int kExitFailed = 1, kExitBadInput = 2;

  // out_help: what --out is ("Metrics file to write (JSON)", "Output directory ...").
  StageCommand(std::string name, const std::string& description, const std::string& run_help,
               const std::string& out_help);
  ~StageCommand();
  // --config: the stage's settings, by default data/<file> of the installation or build tree.
  void add_config(const char* file);
  // --study: the study's constants (data/study.toml).
  void add_study();
  // the stage's own options: a path or name, a flag
  void add_option(const std::string& flag, std::string& into, const std::string& help);
  void add_flag(const std::string& flag, bool& into, const std::string& help);
  // --threads: 0 (OpenMP's default) to 4 per processor, as dem2d run's (core/thread_limit.hpp)
  void add_threads(int& into, const std::string& help);

  // Parses the command line; compute() reads and measures (any exception: bad
  // input, exit 2), write(result) writes the outputs (any exception: exit 1)
  // and returns the summary line.
  template <class Compute, class Write>
  int main(int argc, char** argv, Compute compute, Write write) {
    if (const int code = parse(argc, argv); code >= 0) return code;
    decltype(compute()) result;
    try {
      result = compute();
    } catch (const std::bad_alloc&) {
      std::fprintf(stderr,
                   "%s: %s: out of memory (std::bad_alloc): the run and the settings (%s) need more memory than "
                   "this process may have (the machine's free memory, or `ulimit -v`)\n",
                   name_.c_str(), run.c_str(), config.empty() ? "defaults" : config.c_str());
      return kExitFailed;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "%s: %s\n", name_.c_str(), e.what());
      return kExitBadInput;
    }
    std::string summary;
    try {
      summary = write(result);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "%s: %s\n", name_.c_str(), e.what());
      return kExitFailed;
    }
    std::fprintf(stderr, "%s: %s: %s -> %s\n", name_.c_str(), run.c_str(), summary.c_str(), out.c_str());
    return 0;
  }

  std::string run, out, config, study;

 private:
  // the command line parsed and the installation's data found: -1; else the exit code
  // (0 after --help or --version, 2 on a bad command line or installation)
  int parse(int argc, char** argv);

  std::string name_;
  struct Parser;
  std::unique_ptr<Parser> parser_;
};

}  // namespace dem2d::analysis
