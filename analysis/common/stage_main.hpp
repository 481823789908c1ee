// The command line every analysis stage shares (docs/stages.md):
//   <stage> RUN.h5 --out OUT [--config FILE] [--study FILE] [its own options] [--version]
// and its exit codes: 0 done; 1 an output could not be written; 2 bad input
// (run, config, study or events file, command line). Messages start with the
// stage's name; the last line says what was measured and where it went.
#pragma once

#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>
#include <new>
#include <string>

#include "core/share_dir.hpp"
#include "core/version.hpp"

namespace dem2d::analysis {

class StageCommand {
 public:
  static constexpr int kExitFailed = 1, kExitBadInput = 2;

  // out_help: what --out is ("Metrics file to write (JSON)", "Output directory ...").
  StageCommand(std::string name, const std::string& description, const std::string& run_help,
               const std::string& out_help)
      : name_(std::move(name)), app_(name_ + ": " + description) {
    app_.add_option("run", run, run_help)->required();
    app_.add_option("--out", out, out_help)->required();
    app_.set_version_flag("--version", name_ + " (dem2d) " + code_version());
  }
  CLI::App& app() { return app_; }
  // --config: the stage's settings, by default data/<file> of the installation or build tree.
  void add_config(const char* file) {
    config = data_file(file);
    app_.add_option("--config", config, "Settings (TOML)")->capture_default_str();
  }
  // --study: the study's constants (data/study.toml).
  void add_study() {
    study = data_file("study.toml");
    app_.add_option("--study", study, "The study's constants (TOML)")->capture_default_str();
  }

  // Parses the command line; compute() reads and measures (any exception: bad
  // input, exit 2), write(result) writes the outputs (any exception: exit 1)
  // and returns the summary line.
  template <class Compute, class Write>
  int main(int argc, char** argv, Compute compute, Write write) {
    try {
      app_.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
      return app_.exit(e) == 0 ? 0 : kExitBadInput;
    }
    if (const std::string problem = share_problem(); !problem.empty()) {  // (its data, its code version)
      std::fprintf(stderr, "%s: %s\n", name_.c_str(), problem.c_str());
      return kExitBadInput;
    }
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
  std::string name_;
  CLI::App app_;
};

}  // namespace dem2d::analysis
