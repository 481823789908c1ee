// A fresh directory for a test, named after the test, an optional tag and the
// process (ctest runs tests side by side: they never share one), removed
// afterwards unless DEM2D_KEEP_TEST_FILES is set.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

namespace dem2d::test {

class TempDir {
 public:
  explicit TempDir(const std::string& tag = "") {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    const std::string test = info ? std::string(info->test_suite_name()) + "_" + info->name() : "test";
    path_ = std::filesystem::temp_directory_path() /
            ("dem2d_" + test + (tag.empty() ? "" : "_" + tag) + "_" + std::to_string(::getpid()));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    if (!std::getenv("DEM2D_KEEP_TEST_FILES")) std::filesystem::remove_all(path_);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const std::filesystem::path& path() const { return path_; }
  // path/name as a directory that exists
  std::filesystem::path sub(const std::string& name) const {
    std::filesystem::create_directories(path_ / name);
    return path_ / name;
  }
  // path/name as a file, written with `text` if given
  std::string file(const std::string& name, const std::string& text = "") const {
    const std::filesystem::path p = path_ / name;
    if (!text.empty()) std::ofstream(p) << text;
    return p.string();
  }

 private:
  std::filesystem::path path_;
};

}  // namespace dem2d::test
