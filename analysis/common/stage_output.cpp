#include "common/stage_output.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "runfile/h5.hpp"

namespace dem2d::analysis {

void H5Output::write(const std::string& path) const {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::path(path).has_parent_path()) fs::create_directories(fs::path(path).parent_path(), ec);
  try {
    h5::write_atomically(path, [&](const h5::File& f) {
      for (const Dataset& d : datasets_) {
        std::visit([&](const auto& v) { h5::write(f, d.name, v, d.shape); }, d.data);
        h5::write_attr(f, d.name, "units", d.units);
        h5::write_attr(f, d.name, "description", d.description);
      }
      for (const Attribute& a : attributes_)
        std::visit([&](const auto& v) { h5::write_attr(f, a.object, a.name, v); }, a.value);
    });
  } catch (const std::exception& e) {
    const std::string what = e.what();
    throw std::runtime_error(what.rfind(path, 0) == 0 ? what : path + ": cannot write (" + what + ")");
  }
}

nlohmann::ordered_json number_or_null(double v) { return std::isfinite(v) ? nlohmann::ordered_json(v) : nullptr; }

nlohmann::ordered_json fraction_or_null(std::int64_t num, std::int64_t den) {
  return den > 0 ? nlohmann::ordered_json(static_cast<double>(num) / static_cast<double>(den)) : nullptr;
}

std::string format_mm(double metres) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g mm", metres * 1e3);
  return buf;
}

std::string format_number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

std::string show_metric(const nlohmann::ordered_json& v, const char* unit) {
  if (v.is_null()) return "n/a";
  if (!v.is_number()) return v.dump();
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.4g%s", v.get<double>(), unit);
  return buf;
}

}  // namespace dem2d::analysis
