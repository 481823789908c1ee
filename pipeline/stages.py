#!/usr/bin/python3
"""The registry of analysis stages (pipeline/stages.toml): read and checked
here, for the Makefile and every script that needs the list of stages.

    python3 pipeline/stages.py make [pipeline/stages.toml]   Make rules of the stages, on stdout
    python3 pipeline/stages.py names [pipeline/stages.toml]  the stage names, one per line

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
KEYS = {"name", "program", "run", "config", "inputs", "args", "outputs", "threads"}


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

    @property
    def is_simulation_report(self) -> bool:
        """The stage named like its simulation reports that simulation's cost."""
        return self.name == self.run

    def after(self) -> list:
        """The earlier stages whose outputs this one reads."""
        return sorted({p.split("/")[0] for p in self.inputs.values() if p != BED})


def load(path: Path = REGISTRY) -> list:
    try:
        with open(path, "rb") as f:
            entries = tomllib.load(f).get("stage", [])
    except (OSError, tomllib.TOMLDecodeError) as e:
        raise RegistryError(f"{path}: {e}")
    stages = []
    for k, e in enumerate(entries):
        where = f"{path}: stage[{k}]" + (f" ({e['name']})" if isinstance(e.get("name"), str) else "")

        def bad(key, why):
            return RegistryError(f"{where}: {key} = {e.get(key)!r}: {why}")

        for key in e:
            if key not in KEYS:
                raise RegistryError(f"{where}: unknown key '{key}' (allowed: {', '.join(sorted(KEYS))})")
        for key in ("name", "program", "run", "outputs"):
            if key not in e:
                raise RegistryError(f"{where}: missing key '{key}'")
        if not isinstance(e["name"], str) or not re.fullmatch(r"[a-z][a-z0-9_]*", e["name"]):
            raise bad("name", "must be a lower-case identifier")
        if e["name"] in (s.name for s in stages):
            raise bad("name", "another stage has this name")
        if not isinstance(e["program"], str) or not re.fullmatch(r"[a-z][a-z0-9_]*", e["program"]):
            raise bad("program", "must be a program name (build/release/analysis/<program>)")
        if e["run"] not in SIMULATIONS:
            raise bad("run", f"allowed: {', '.join(SIMULATIONS)}")
        config = e.get("config", "")
        if config and not (REPO / config).is_file():
            raise bad("config", "no such file in the repository")
        inputs = e.get("inputs", {})
        if not isinstance(inputs, dict):
            raise bad("inputs", "must be a table { \"--flag\" = \"<stage>/<file>\" }")
        earlier = {s.name: s for s in stages}
        for flag, p in inputs.items():
            if not flag.startswith("--") or not isinstance(p, str):
                raise bad("inputs", f"'{flag}' = {p!r}: a --flag and a path \"<stage>/<file>\"")
            stage, _, name = p.partition("/")
            if p != BED and (stage not in earlier or name not in earlier[stage].outputs):
                raise bad("inputs", f"'{flag}' = '{p}': not an output of an earlier stage (earlier: "
                                    + ", ".join(f"{s}/{o}" for s in earlier for o in earlier[s].outputs)
                                    + f", or {BED})")
        args = e.get("args", [])
        if not isinstance(args, list) or not all(isinstance(a, str) for a in args):
            raise bad("args", "must be an array of strings")
        outputs = e["outputs"]
        if not isinstance(outputs, list) or not outputs or outputs[-1] != "metrics.json":
            raise bad("outputs", "must be an array of file names ending with \"metrics.json\" (written last)")
        threads = e.get("threads", False)
        if not isinstance(threads, bool):
            raise bad("threads", "must be true or false")
        stages.append(Stage(e["name"], e["program"], e["run"], config, dict(inputs), list(args),
                            list(outputs), threads))
    if not stages:
        raise RegistryError(f"{path}: no [[stage]] entries")
    return stages


def make_rules(stages: list, registry: str) -> str:
    """Make rules of the stages; they use the Makefile's STAGE_BIN, RESULTS, FILL_RUN,
    THREADS and its `timed` function."""
    run_file = {"fill": "$(FILL_RUN)", "pulloff": "$(RESULTS)/pulloff/run.h5"}
    out = [f"# Generated from {registry} by pipeline/stages.py: do not edit.",
           f"STAGES := {' '.join(s.name for s in stages)}"]
    programs = []
    for s in stages:
        var = s.program.upper()
        out.append(f"{var} := $(STAGE_BIN)/{s.program}")
        programs.append(f"$({var})")
    out.append(f"STAGE_PROGRAMS := {' '.join(dict.fromkeys(programs))}")
    out.append("STAGE_METRICS := $(foreach s,$(STAGES),$(RESULTS)/$(s)/metrics.json)")
    out.append(f".PHONY: {' '.join(s.name for s in stages)}")
    for s in stages:
        prog = f"$({s.program.upper()})"
        deps = [run_file[s.run]]
        deps += ["$(FILL_RUN)" if p == BED else f"$(RESULTS)/{p.split('/')[0]}/metrics.json"
                 for p in s.inputs.values()]
        deps += ([s.config] if s.config else []) + ["data/study.toml", prog]
        cmd = [prog, run_file[s.run], "--out", "$(@D)"]
        if s.config:
            cmd += ["--config", s.config]
        for flag, p in s.inputs.items():
            cmd += [flag, "$(FILL_RUN)" if p == BED else f"$(RESULTS)/{p}"]
        cmd += [a.replace("{dir}", "$(@D)") for a in s.args]
        if s.threads:
            cmd += ["--threads", "$(THREADS)"]
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
