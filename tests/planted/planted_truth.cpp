// planted_truth: the planted-truth suite of the analysis stages' detectors
// (tests/planted/planted.hpp), run by make validate and, its quick set, by
// make test.
//   planted_truth --data DIR [--quick] [--only FAMILY] [--json FILE]   (FAMILY: drag, cg, network, stress)
// Prints one line per case (planted, recovered mean +- sd over the replicas,
// found/replicas, pass); --json writes the rows. Exit status: 0 every judged
// case passes, 1 one fails, 2 bad input.
#include <chrono>
#include <cstdio>
#include <cstring>
#include <exception>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "planted/planted.hpp"

namespace {

using Family = std::vector<dem2d::planted::Row> (*)(const dem2d::planted::Settings&, const std::string&);
// the families of cases, in the order they run: the one list
const std::pair<const char*, Family> kFamilies[] = {{"drag", dem2d::planted::drag_cases},
                                                    {"cg", dem2d::planted::cg_cases},
                                                    {"network", dem2d::planted::network_cases},
                                                    {"stress", dem2d::planted::stress_cases},
                                                    {"piv", dem2d::planted::piv_cases}};

int usage(const char* argv0) {
  std::string names;
  for (const auto& [name, run] : kFamilies) names += std::string(names.empty() ? "" : "|") + name;
  std::fprintf(stderr, "usage: %s --data DIR [--quick] [--only %s] [--json FILE]\n", argv0, names.c_str());
  return 2;
}

bool known(const std::string& family) {
  for (const auto& [name, run] : kFamilies)
    if (family == name) return true;
  return false;
}

void print(const dem2d::planted::Row& r) {
  auto v = [](double x) { return std::isfinite(x) ? std::to_string(x).substr(0, 8) : std::string("none"); };
  std::printf("%-5s %-22s | %-70s | noise %-5g %-4s | planted %-8s | mean %-8s sd %-8s | found %d/%d\n",
              !r.limit.empty() ? "limit" : !r.judged ? "info" : r.pass ? "pass" : "FAIL", r.detector.c_str(), r.name.c_str(), r.noise,
              r.noise_unit.c_str(), v(r.planted).c_str(), v(r.mean).c_str(), v(r.sd).c_str(), r.found, r.replicas);
}

}  // namespace

int main(int argc, char** argv) {
  std::string data, only, json;
  bool quick = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--quick") quick = true;
    else if (a == "--data" && i + 1 < argc) data = argv[++i];
    else if (a == "--only" && i + 1 < argc) only = argv[++i];
    else if (a == "--json" && i + 1 < argc) json = argv[++i];
    else return usage(argv[0]);
  }
  if (data.empty() || (!only.empty() && !known(only))) return usage(argv[0]);
  using namespace dem2d::planted;
  std::vector<Row> rows;
  nlohmann::ordered_json seconds = nlohmann::ordered_json::object();
  try {
    const Settings s = load_settings(data + "/planted.toml", quick);
    for (const auto& [name, run] : kFamilies) {
      if (!only.empty() && only != name) continue;
      const auto t0 = std::chrono::steady_clock::now();
      for (const Row& r : run(s, data)) {
        print(r);
        std::fflush(stdout);
        rows.push_back(r);
      }
      seconds[name] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "planted_truth: %s\n", e.what());
    return 2;
  }
  int judged = 0, passed = 0;
  for (const Row& r : rows) judged += r.judged, passed += r.judged && r.pass;
  std::printf("%d of %d judged cases pass (%zu rows)\n", passed, judged, rows.size());
  if (!json.empty()) {
    nlohmann::ordered_json j = {{"rows", nlohmann::ordered_json::array()}, {"seconds", seconds}};
    for (const Row& r : rows) j["rows"].push_back(to_json(r));
    std::ofstream out(json + ".tmp");
    out << j.dump(1) << "\n";
    out.close();
    if (!out || std::rename((json + ".tmp").c_str(), json.c_str()) != 0) {
      std::fprintf(stderr, "planted_truth: cannot write %s\n", json.c_str());
      return 1;
    }
  }
  return passed == judged ? 0 : 1;
}
