// An earlier stage's JSON output read as an input (--fill-metrics,
// --spectrum-metrics, --cg-metrics): through the settings' bounded reader
// (toml/toml_reader.hpp: a regular file or a pipe with a writer, at most
// 256 MiB), then parsed. Every failure is a StageError naming the file.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace dem2d::analysis {

// "FILE: no such file (<what>)", "FILE: cannot read the <what>: not a regular file" (a folder, a device,
// a pipe nothing writes to), "FILE: not JSON (<parser's message>)".
nlohmann::json read_json(const std::string& path, const char* what);

}  // namespace dem2d::analysis
