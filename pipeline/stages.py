"""The registry of analysis stages (pipeline/stages.toml): read and checked
here, for the Makefile and every script that needs the list of stages.

    python3 -m pipeline.stages make [pipeline/stages.toml]   Make rules of the stages, on stdout
    python3 -m pipeline.stages names [pipeline/stages.toml]  the stage names, one per line

From Python: `from stages import load; for s in load(): s.name, s.outputs, ...`
(pipeline/ on sys.path). A bad entry is an error naming the file, the entry,
the key, the value and what is allowed (exit code 2).
"""
import re
import sys
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
REGISTRY = REPO / "pipeline" / "stages.toml"
SIMULATIONS = ("fill", "pulloff")  # the run files the Makefile's dem2d rules make
BED = "fill/run.h5"                # the bed: $(FILL_RUN), which a sweep may take from elsewhere
KEYS = {"name", "program", "run", "config", "inputs", "args", "outputs", "threads", "reads"}
# What of its run file a stage reads (its `reads`): a value it reads there that is damaged (NaN, missing, the
# wrong shape) must make it fail (tests/fuzz/fuzz.py holds every stage to what it declares).
READS = {"series": "the drag series (series/time, body_force_mean, body_vertices)",
         "snapshots": "every snapshot's positions and velocities",
         "last snapshot": "the last snapshot's positions and velocities",
         "sampled snapshots": "the snapshots its settings pick (a damaged one may be one it skips)",
         "contacts": "every snapshot's contacts",
         "last contacts": "the last snapshot's contacts"}
# What a stage may not be named: its name becomes a make target and a results folder
RESERVED = {"all", "default", "FORCE", "stages", "registries", "figures", "metrics", "ensemble", "members"}


def makefile_text() -> str:
    """The Makefile's text ("" where it cannot be read: nothing is then reserved by it)."""
    try:
        return (REPO / "Makefile").read_text()
    except OSError:
        return ""


def makefile_targets() -> set:
    """The Makefile's own targets (`name:` at the start of a line): a stage named like one would take it over."""
    return {t for line in re.findall(r"^([A-Za-z][\w .-]*?)\s*::?(?!=)", makefile_text(), re.M) for t in line.split()}


def makefile_folders() -> set:
    """The folders the Makefile's own rules write under a preset's results ($(RESULTS)/<name>): a stage of
    that name would write into one (the pull-off slice's pulloff_5mm among them)."""
    return set(re.findall(r"\$\(RESULTS\)/([A-Za-z0-9_]+)", makefile_text()))


# the slice on another preset's bed: $(RESULTS)/pulloff_5mm_on_<preset>_bed (Makefile, SLICE_DIR)
SLICE_ON_BED = re.compile(r"pulloff_5mm_on_.*_bed")


MAKE_ESCAPES = {"$": "$$", ",": "$(comma)", "(": "$(lparen)", ")": "$(rparen)"}  # (pipeline/make_vars.mk)


def shell_word(text: str) -> str:
    """`text` as one word for the shell inside a $(call timed,...) recipe: single-quoted for the shell, and
    what make would read (a `$`, and the commas and parentheses of the call) escaped."""
    quoted = "'" + text.replace("'", "'\\''") + "'"
    return "".join(MAKE_ESCAPES.get(c, c) for c in quoted)


class RegistryError(Exception):
    pass


@dataclass
class Stage:
    name: str
    program: str
    run: str
    config: str = ""
    inputs: dict = field(default_factory=dict)
    args: list = field(default_factory=list)
    outputs: list = field(default_factory=list)
    threads: bool = False
    reads: tuple = ()

    @property
    def is_simulation_report(self) -> bool:
        """The stage named like its simulation reports that simulation's cost."""
        return self.name == self.run

    def after(self) -> list:
        """The earlier stages whose outputs this one reads."""
        return sorted({p.split("/")[0] for p in self.inputs.values() if p != BED})


IDENTIFIER = r"[a-z][a-z0-9_]{0,63}"  # a stage's name and program: a lower-case identifier, 64 characters at most


def short(value) -> str:
    """A value or key as a message shows it: at most 60 characters of its repr."""
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def is_file(path: Path) -> bool:
    try:
        return path.is_file()
    except OSError:  # (a name too long, say)
        return False


def load(path: Path = REGISTRY) -> list:
    try:
        with open(path, "rb") as f:
            doc = tomllib.load(f)
    except (OSError, tomllib.TOMLDecodeError) as e:
        raise RegistryError(f"{path}: {e}")
    unknown = sorted(set(doc) - {"stage"})
    if unknown:
        raise RegistryError(f"{path}: unknown key {short(unknown[0])} (allowed: [[stage]] entries)")
    entries = doc.get("stage", [])
    if not isinstance(entries, list) or not all(isinstance(e, dict) for e in entries):
        raise RegistryError(f"{path}: stage = {short(entries)}: must be [[stage]] tables")
    reserved = RESERVED | makefile_targets() | (makefile_folders() - set(SIMULATIONS))
    stages = []
    for k, e in enumerate(entries):
        where = f"{path}: stage[{k}]" + (f" ({e['name'][:60]})" if isinstance(e.get("name"), str) else "")

        def bad(key, why):
            return RegistryError(f"{where}: {key} = {short(e.get(key))}: {why}")

        for key in e:
            if key not in KEYS:
                raise RegistryError(f"{where}: unknown key {short(key)} (allowed: {', '.join(sorted(KEYS))})")
        for key in ("name", "program", "run", "outputs"):
            if key not in e:
                raise RegistryError(f"{where}: missing key '{key}'")
        if not isinstance(e["name"], str) or not re.fullmatch(IDENTIFIER, e["name"]):
            raise bad("name", "must be a lower-case identifier of at most 64 characters")
        if e["name"] in (s.name for s in stages):
            raise bad("name", "another stage has this name")
        if (e["name"] in reserved or SLICE_ON_BED.fullmatch(e["name"])
                or e["name"] in SIMULATIONS and e["name"] != e["run"]):
            raise bad("name", "a name the Makefile uses already (a target, or a folder of its own rules)")
        if not isinstance(e["program"], str) or not re.fullmatch(IDENTIFIER, e["program"]):
            raise bad("program", "must be a program name of at most 64 characters (build/release/analysis/<program>)")
        if e["run"] not in SIMULATIONS:
            raise bad("run", f"allowed: {', '.join(SIMULATIONS)}")
        config = e.get("config", "")
        if not isinstance(config, str) or config and not (
                re.fullmatch(r"[A-Za-z0-9_./-]+", config) and not config.startswith("/") and ".." not in config.split("/")
                and is_file(REPO / config)):
            raise bad("config", "must be a settings file in the repository, given relative to it (data/<stage>.toml)")
        inputs = e.get("inputs", {})
        if not isinstance(inputs, dict):
            raise bad("inputs", "must be a table { \"--flag\" = \"<stage>/<file>\" }")
        earlier = {s.name: s for s in stages}
        for flag, p in inputs.items():
            if not re.fullmatch(r"--[a-z][a-z0-9-]{0,63}", flag) or not isinstance(p, str):
                raise bad("inputs", f"{short(flag)} = {short(p)}: a --flag and a path \"<stage>/<file>\"")
            stage, _, name = p.partition("/")
            if p != BED and (stage not in earlier or name not in earlier[stage].outputs):
                raise bad("inputs", f"{short(flag)} = {short(p)}: not an output of an earlier stage (earlier: "
                                    + ", ".join(f"{s}/{o}" for s in earlier for o in earlier[s].outputs)
                                    + f", or {BED})")
        args = e.get("args", [])
        if not isinstance(args, list) or not all(isinstance(a, str) and a.isprintable() for a in args):
            raise bad("args", "must be an array of strings (printable: no line breaks)")
        outputs = e["outputs"]
        if (not isinstance(outputs, list) or not outputs or outputs[-1] != "metrics.json"
                or not all(isinstance(o, str) and re.fullmatch(r"[A-Za-z0-9_][A-Za-z0-9_.-]*", o) for o in outputs)):
            raise bad("outputs", "must be an array of file names (letters, digits, _ . -) ending with "
                                 "\"metrics.json\" (written last)")
        threads = e.get("threads", False)
        if not isinstance(threads, bool):
            raise bad("threads", "must be true or false")
        reads = e.get("reads", [])
        if not isinstance(reads, list) or not all(r in READS for r in reads) or len(set(reads)) != len(reads):
            raise bad("reads", "must be an array of distinct values among " + ", ".join(f'"{r}"' for r in READS))
        stages.append(Stage(e["name"], e["program"], e["run"], config, dict(inputs), list(args),
                            list(outputs), threads, tuple(reads)))
    if not stages:
        raise RegistryError(f"{path}: no [[stage]] entries")
    return stages


def make_rules(stages: list, registry: str) -> str:
    """Make rules of the stages; they use the Makefile's STAGE_BIN, RESULTS, FILL_RUN,
    THREADS_OPTION and its `timed` function."""
    run_file = {"fill": "$(FILL_RUN)", "pulloff": "$(RESULTS)/pulloff/run.h5"}
    # every variable it defines starts with STAGE (the Makefile's own never do): a program's name
    # cannot replace one of the Makefile's variables (python, path, shell...)
    out = [f"# Generated from {registry} by pipeline/stages.py: do not edit.",
           f"STAGES := {' '.join(s.name for s in stages)}"]
    programs = []
    for s in stages:
        var = f"STAGE_PROGRAM_{s.program}"
        out.append(f"{var} := $(STAGE_BIN)/{s.program}")
        programs.append(f"$({var})")
    out.append(f"STAGE_PROGRAMS := {' '.join(dict.fromkeys(programs))}")
    out.append("STAGE_METRICS := $(foreach s,$(STAGES),$(RESULTS)/$(s)/metrics.json)")
    out.append(f".PHONY: {' '.join(s.name for s in stages)}")
    for s in stages:
        prog = f"$(STAGE_PROGRAM_{s.program})"
        deps = [run_file[s.run]]
        deps += ["$(FILL_RUN)" if p == BED else f"$(RESULTS)/{p.split('/')[0]}/metrics.json"
                 for p in s.inputs.values()]
        deps += ([s.config] if s.config else []) + ["data/study.toml", prog]
        cmd = [prog, run_file[s.run], "--out", "$(@D)"]
        if s.config:
            cmd += ["--config", s.config]
        for flag, p in s.inputs.items():
            cmd += [flag, "$(FILL_RUN)" if p == BED else f"$(RESULTS)/{p}"]
        # every argument one shell word, taken as written (no make or shell expansion); {dir}: the stage's folder
        cmd += ["'$(@D)'".join(shell_word(piece) for piece in a.split("{dir}")) for a in s.args]
        if s.threads:
            cmd += ["$(THREADS_OPTION)"]  # (empty, or --threads N)
        target = f"$(RESULTS)/{s.name}/metrics.json"
        out.append(f"{target}: {' '.join(dict.fromkeys(deps))}")
        out.append("\t@mkdir -p $(@D)")
        out.append(f"\t@$(call timed,{' '.join(cmd)})")
        out.append(f"{s.name}: {target}")
    return "\n".join(out) + "\n"


def main(argv: list) -> int:
    if len(argv) not in (2, 3) or argv[1] not in ("make", "names"):
        print(__doc__, file=sys.stderr)
        return 2
    path = Path(argv[2]) if len(argv) == 3 else REGISTRY
    try:
        stages = load(path)
    except RegistryError as e:
        print(f"stages: {e}", file=sys.stderr)
        return 2
    if argv[1] == "make":
        sys.stdout.write(make_rules(stages, str(argv[2]) if len(argv) == 3 else "pipeline/stages.toml"))
    else:
        print("\n".join(s.name for s in stages))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
