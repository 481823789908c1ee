#include "common/json_input.hpp"

#include <filesystem>

#include "common/stage_config.hpp"

namespace dem2d::analysis {

nlohmann::json read_json(const std::string& path, const char* what) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw StageError(path + ": no such file (" + what + ")");
  const std::string text = StageFile(path).read(what);
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw StageError(path + ": not JSON (" + e.what() + ")");
  }
}

}  // namespace dem2d::analysis
