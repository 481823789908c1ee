// dem2d: the command line.
//   dem2d run SCENE.toml --out DIR [--overlay FILE]... [--initial RUN.h5|CHECKPOINT.h5] [--threads N] [--fresh] [--overwrite] [--progress S]
//             [--generic-kernel]
//   dem2d check SCENE.toml [--overlay FILE]... [--initial RUN.h5|CHECKPOINT.h5] [--json]
//   dem2d bench [--scene FILE] [--steps N] [--threads 1,2] [--passes | --tiles K... | --list]
//   dem2d inspect RUN.h5 | --schema   (--schema: the run file's layout, JSON)
//   dem2d --list-effects   the effects this build knows (JSON: key, bit, needs, what)
// Exit codes: 0 done, 1 run failed, 2 bad input, 3 interrupted (checkpoint written).
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <omp.h>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <exception>
#include <new>
#include <string>
#include <string_view>
#include <vector>

#include "app/bench.hpp"
#include "app/inspect.hpp"
#include "core/effects.hpp"
#include "core/share_dir.hpp"
#include "core/thread_limit.hpp"
#include "core/version.hpp"
#include "engine/kernel_sets.hpp"
#include "run/output_dir.hpp"
#include "run/run.hpp"
#include "run/thread_choice.hpp"
#include "scene/scene_toml.hpp"
#include "toml/toml_reader.hpp"  // did_you_mean, show_key
#include "writer/run_file_describe.hpp"

namespace {

constexpr int kExitFailed = 1, kExitBadInput = 2, kExitInterrupted = 3;

extern "C" void on_signal(int sig) {
  dem2d::request_interrupt();
  std::signal(sig, SIG_DFL);  // a second signal stops at once
}

int cmd_check(const std::string& path, const dem2d::SceneSources& extra, bool json) {
  const dem2d::Scene s = dem2d::load_scene(path, extra);
  const dem2d::StabilityLimit limit = s.stability_limit();
  const bool damped = dem2d::has(s.effects, dem2d::effect::normal_damping);
  const double nu_pp = damped ? dem2d::damping_ratio(s.particle_particle.restitution) : 0.0;
  const double nu_pw = damped ? dem2d::damping_ratio(s.particle_wall.restitution) : 0.0;
  const auto steps = static_cast<long long>(s.stop.duration / s.dt + 0.5);
  if (json) {  // the same numbers for scripts (e.g. make bench-compare's LAMMPS input)
    const nlohmann::json j = {{"scene", path},
                              {"particles", s.particles.size()},
                              {"bodies", s.bodies.size()},
                              {"effects", dem2d::effect_names(s.effects)},
                              {"kernel", dem2d::kernels_specialised(s.effects) ? "specialised" : "generic"},
                              {"dt_s", s.dt},
                              {"critical_dt_s", s.critical_dt()},
                              {"stable_dt_s", limit.dt},
                              {"stable_dt_over_critical", limit.dt_over_critical},
                              {"fastest_mode", limit.mode},
                              {"steps", steps},
                              {"normal_damping_ratio", {{"grains", nu_pp}, {"walls", nu_pw}}}};
    std::printf("%s\n", j.dump(2).c_str());
    return 0;
  }
  std::printf("%s: valid\n  particles %zu, bodies %zu\n  effects: %s\n", path.c_str(), s.particles.size(),
              s.bodies.size(), s.effects ? dem2d::effect_names(s.effects, ", ").c_str() : "none");
  std::printf("  runs on the %s\n", dem2d::kernel_description(s.effects).c_str());
  std::printf("  dt = %.6g s = dt_c/%.4g (dt_c = %.6g s), %lld steps for %.6g s\n", s.dt, s.critical_dt() / s.dt,
              s.critical_dt(), steps, s.stop.duration);
  std::printf("  stability limit dt_s = %.6g s = %.4g dt_c (fastest mode: %s); dt = %.3g dt_s\n", limit.dt,
              limit.dt_over_critical, limit.mode.c_str(), s.dt / limit.dt);
  if (damped)
    std::printf("  normal damping ratio nu = %.6g for e = %.6g (grains), %.6g for e = %.6g (walls)\n", nu_pp,
                s.particle_particle.restitution, nu_pw, s.particle_wall.restitution);
  return 0;
}

int cmd_run(const std::string& path, const dem2d::SceneSources& extra, dem2d::RunOptions opt, int threads,
            bool generic_kernel) {
  dem2d::Scene scene = dem2d::load_scene(path, extra);
  scene.generic_kernel = generic_kernel;
  if (threads == 0) {
    const int cores = std::max(omp_get_num_procs(), 1);
    const dem2d::ThreadChoice c = dem2d::choose_threads(scene.particles.size(), cores, dem2d::free_cores_now(cores));
    scene.threads = c.threads;
    opt.threads_why = c.why;
  } else {
    scene.threads = threads;
    opt.threads_why = dem2d::threads_text(threads) + " (--threads)";
  }
  opt.progress.terminal = isatty(STDERR_FILENO) != 0;
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  const dem2d::RunReport r = dem2d::run_scene(scene, opt);
  if (r.already_complete) {
    std::fprintf(stderr,
                 "dem2d: %s is complete: this scene's run, from the same starting state, by this dem2d version; "
                 "nothing to do (--overwrite runs it again)\n",
                 r.stop_reason.c_str());
    return 0;
  }
  if (!r.complete) {
    std::fprintf(stderr, "dem2d: interrupted at step %lld; checkpoint in %s/.run.work, rerun the same command to resume\n",
                 static_cast<long long>(r.final_step), opt.out_dir.c_str());
    return kExitInterrupted;
  }
  std::fprintf(stderr,
               "dem2d: %s%s: %lld steps in %.1f s (%.3g ns per particle-step; %lld list rebuilds, %.2f candidate "
               "pairs per grain), %s%s\n",
               r.run_file.c_str(), r.resumed ? " (resumed)" : "", static_cast<long long>(r.steps),
               r.wall_seconds, r.ns_per_particle_step, static_cast<long long>(r.rebuilds), r.candidates_per_grain,
               r.stop_reason.c_str(),
               r.lost ? (", " + std::to_string(r.lost) + " particles left the domain").c_str() : "");
  return 0;
}

// The effects of this build, from the one list (core/effects.hpp), as JSON on stdout.
void list_effects() {
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  for (const dem2d::EffectName& e : dem2d::kEffectNames) {
    const nlohmann::ordered_json needs = e.needs ? nlohmann::ordered_json(dem2d::effect_names(e.needs)) : nullptr;
    out.push_back({{"key", e.key}, {"bit", e.bit}, {"needs", needs}, {"what", e.what}});
  }
  std::printf("%s\n", out.dump(2).c_str());
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"dem2d: 2D discrete element simulation of frictional disks and sphero-lines"};
  app.set_version_flag("--version", dem2d::code_version());
  app.add_flag_callback(
      "--list-effects", [] { list_effects(); throw CLI::Success(); },
      "Print the effects a scene may name (JSON: key, bit, what it needs, what it does) and exit");
  app.require_subcommand(1);

  std::string scene_path;
  dem2d::SceneSources extra;
  dem2d::RunOptions run_opt;
  int threads = 0;
  bool generic_kernel = false;
  const CLI::Validator thread_count(dem2d::thread_count_problem, "0.." + std::to_string(dem2d::max_threads()));
  auto scene_options = [&](CLI::App* cmd) {
    cmd->add_option("scene", scene_path, "Scene file (TOML)")->required();
    cmd->add_option("--overlay", extra.overlays, "TOML file merged over the scene, e.g. a preset (repeatable)");
    cmd->add_option("--initial", extra.initial_run,
                    "Run file whose final state the grains start from, or a checkpoint (DIR/.run.work/checkpoint.h5 "
                    "of an unfinished run: its state, with this scene's settings)");
  };
  auto* run = app.add_subcommand("run", "Run a scene; writes DIR/run.h5 and DIR/run.xdmf");
  scene_options(run);
  run->add_option("--out", run_opt.out_dir, "Output directory")->required();
  run->add_option("--threads", threads,
                  "OpenMP threads (default 0: chosen from the scene's size and the cores free now)")
      ->check(thread_count);
  run->add_flag("--generic-kernel", generic_kernel,
                "Run on the generic kernel (the effects tested at run time) even where this build has one "
                "specialised for the scene's effects: the same results, slower");
  run->add_flag("--fresh", run_opt.fresh, "Discard a checkpoint in DIR instead of resuming from it");
  run->add_flag("--overwrite", run_opt.overwrite,
                "Replace DIR/run.h5 and DIR/run.xdmf: a finished run (of this scene or another; says what goes "
                "stale), or files that are not a dem2d run's (never through a link)");
  run->add_option("--progress", run_opt.progress.every,
                  "Seconds of wall time between progress lines in DIR/run.log, and on stderr when it is not a "
                  "terminal (0: none)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1e9));
  run->add_option("--interrupt-at-step", run_opt.interrupt_at_step,
                  "Testing: checkpoint and stop as if interrupted at this step")
      ->group("");  // for the tests: not in --help

  auto* check = app.add_subcommand("check", "Validate a scene file and print its summary");
  scene_options(check);
  bool check_json = false;
  check->add_flag("--json", check_json, "Print the summary as JSON (stdout)");

  dem2d::BenchOptions bench_opt;
  auto* bench = app.add_subcommand("bench", "ns per particle-step on a settled bed, per effect set and thread count");
  bench->add_option("--scene", bench_opt.scene, "Bed to settle and measure")->capture_default_str();
  bench->add_option("--steps", bench_opt.steps, "Timed steps per measurement")->capture_default_str();
  bench->add_option("--repeat", bench_opt.repeat, "Measurements per case (best is kept)")->capture_default_str();
  bench->add_option("--threads", bench_opt.threads, "Thread counts")->capture_default_str()->check(thread_count);
  bench->add_option("--json", bench_opt.json, "Also write the results as JSON to this file");
  bench->add_option("--tiles", bench_opt.tiles,
                    "Scaling instead: time K copies of the settled bed side by side in one wider cell, for each K")
      ->check(CLI::PositiveNumber);
  bench->add_flag("--list", bench_opt.list,
                  "List the cases and the kernel each runs on (specialised or generic), without running them");
  bench->add_flag("--passes", bench_opt.passes,
                  "Where the time goes instead: each thread's time per pass of the step, full contact law");
  bench->add_option("--particle-steps", bench_opt.particle_steps,
                    "Scaling: particle-steps per measurement (steps = this / N)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);

  std::string inspect_path;
  auto* inspect = app.add_subcommand("inspect", "Read a whole run file with every check the analyses apply, and "
                                                "say what it holds (exit 2 if it is damaged)");
  inspect->add_option("run", inspect_path, "Run file (run.h5)");
  bool inspect_schema = false;
  inspect->add_flag("--schema", inspect_schema,
                    "Print the run file's schema instead (JSON: attributes, datasets with type, shape, unit and "
                    "meaning, the energy ledger's terms, the effects) and exit");

  // A misspelt command: say which, and the nearest (CLI11 says only that one is required).
  if (argc > 1 && argv[1][0] != '-') {
    const std::vector<std::string_view> commands = {"run", "check", "bench", "inspect"};
    if (std::find(commands.begin(), commands.end(), std::string_view(argv[1])) == commands.end()) {
      std::fprintf(stderr, "dem2d: unknown command '%s' (commands: run, check, bench, inspect)%s\n",
                   dem2d::show_key(argv[1]).c_str(), dem2d::did_you_mean(argv[1], commands).c_str());
      return kExitBadInput;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;  // --help, --version: 0; a bad command line: 2, as bad input
  }
  if (const std::string problem = dem2d::share_problem(); !problem.empty()) {  // its data, its code version
    std::fprintf(stderr, "dem2d: %s\n", problem.c_str());
    return kExitBadInput;
  }
  try {
    if (*run) return cmd_run(scene_path, extra, run_opt, threads, generic_kernel);
    if (*check) return cmd_check(scene_path, extra, check_json);
    if (*bench) return dem2d::run_bench(bench_opt);
    if (*inspect && inspect_schema) {
      std::fputs(dem2d::run_file_schema_json().c_str(), stdout);
      return 0;
    }
    if (*inspect && inspect_path.empty()) {
      std::fprintf(stderr, "dem2d: inspect: give a run file (dem2d inspect RUN.h5), or --schema\n");
      return kExitBadInput;
    }
    if (*inspect) return dem2d::inspect_run_file(inspect_path);
  } catch (const dem2d::SceneError& e) {
    std::fprintf(stderr, "dem2d: %s\n", e.what());
    return kExitBadInput;
  } catch (const dem2d::OutputDirError& e) {
    std::fprintf(stderr, "dem2d: %s\n", e.what());
    return kExitBadInput;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr,
                 "dem2d: %s: out of memory (std::bad_alloc): the scene needs more memory than this process may "
                 "have (the machine's free memory, or `ulimit -v`); fewer grains, a smaller [domain] or fewer "
                 "outputs need less\n",
                 scene_path.c_str());
    return kExitFailed;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dem2d: %s\n", e.what());
    return kExitFailed;
  }
  return 0;
}
