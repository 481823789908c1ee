#include "common/stage_main.hpp"

#include <CLI/CLI.hpp>

#include "core/share_dir.hpp"
#include "core/thread_limit.hpp"
#include "core/version.hpp"

namespace dem2d::analysis {

struct StageCommand::Parser {
  explicit Parser(const std::string& description) : app(description) {}
  CLI::App app;
};

StageCommand::StageCommand(std::string name, const std::string& description, const std::string& run_help,
                           const std::string& out_help)
    : name_(std::move(name)), parser_(std::make_unique<Parser>(name_ + ": " + description)) {
  parser_->app.add_option("run", run, run_help)->required();
  parser_->app.add_option("--out", out, out_help)->required();
  parser_->app.set_version_flag("--version", name_ + " (dem2d) " + code_version());
}

StageCommand::~StageCommand() = default;

void StageCommand::add_config(const char* file) {
  config = data_file(file);
  parser_->app.add_option("--config", config, "Settings (TOML)")->capture_default_str();
}

void StageCommand::add_study() {
  study = data_file("study.toml");
  parser_->app.add_option("--study", study, "The study's constants (TOML)")->capture_default_str();
}

void StageCommand::add_option(const std::string& flag, std::string& into, const std::string& help) {
  parser_->app.add_option(flag, into, help);
}

void StageCommand::add_threads(int& into, const std::string& help) {
  parser_->app.add_option("--threads", into, help)
      ->check(CLI::Validator(thread_count_problem, "0.." + std::to_string(max_threads())));
}

void StageCommand::add_flag(const std::string& flag, bool& into, const std::string& help) {
  parser_->app.add_flag(flag, into, help);
}

int StageCommand::parse(int argc, char** argv) {
  try {
    parser_->app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return parser_->app.exit(e) == 0 ? 0 : kExitBadInput;
  }
  if (const std::string problem = share_problem(); !problem.empty()) {  // (its data, its code version)
    std::fprintf(stderr, "%s: %s\n", name_.c_str(), problem.c_str());
    return kExitBadInput;
  }
  return -1;
}

}  // namespace dem2d::analysis
