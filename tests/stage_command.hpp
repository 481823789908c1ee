// A stage's command line against the stage contract (common/stage_main.hpp),
// from outside: exit status 2 and nothing written for a missing run file and
// for a bad setting, 1 when the output folder cannot be made (a file is in
// its place), and, if `outputs` are named, 0 with each of them written.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "temp_dir.hpp"

namespace dem2d::test {

// The exit status of a command line (its error output discarded); -1 if it did not exit.
inline int exit_code(const std::string& command_line) {
  const int status = std::system((command_line + " 2>/dev/null").c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

inline void expect_stage_command_contract(const std::string& exe, const std::string& run, const std::string& bad_config,
                                          const std::vector<std::string>& outputs = {}) {
  const TempDir dir("command");
  const std::string out = (dir.path() / "out").string();
  EXPECT_EQ(exit_code(exe + " " + (dir.path() / "missing.h5").string() + " --out " + out), 2);
  EXPECT_EQ(exit_code(exe + " " + run + " --out " + out + " --config " + dir.file("bad.toml", bad_config)), 2);
  EXPECT_FALSE(std::filesystem::exists(out + "/metrics.json"));
  EXPECT_EQ(exit_code(exe + " " + run + " --out " + dir.file("file", "x")), 1);
  if (outputs.empty()) return;
  EXPECT_EQ(exit_code(exe + " " + run + " --out " + out), 0);
  for (const std::string& name : outputs) EXPECT_TRUE(std::filesystem::exists(out + "/" + name)) << name;
}

}  // namespace dem2d::test
