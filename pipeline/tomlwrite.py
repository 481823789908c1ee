"""Writing TOML (Python reads it with tomllib but has no writer): scenes,
overlays and settings the pipeline generates.

    dumps({"name": "x", "contact": {"kn": 1e6, "wall": {"friction": 0.3}}, "body": [{...}, {...}]},
          header="what this file is")

Top-level values first, then tables ([a], [a.b] for nested ones), then arrays
of tables ([[body]]); a table inside an array element is written inline.
"""


def value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        return repr(v)
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(v, list):
        return "[" + ", ".join(value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{ " + ", ".join(f"{k} = {value(x)}" for k, x in v.items()) + " }"
    raise ValueError(f"cannot write {v!r} as TOML")


def is_table_array(v) -> bool:
    return isinstance(v, list) and bool(v) and all(isinstance(x, dict) for x in v)


def table(doc: dict, path: str, lines: list) -> None:
    plain = {k: v for k, v in doc.items() if not isinstance(v, dict) and not is_table_array(v)}
    if path and (plain or not any(isinstance(v, dict) for v in doc.values())):
        lines += ["", f"[{path}]"]
    lines += [f"{k} = {value(v)}" for k, v in plain.items()]
    for k, v in doc.items():
        if isinstance(v, dict):
            table(v, f"{path}.{k}" if path else k, lines)
    for k, v in doc.items():
        if is_table_array(v):
            for element in v:
                lines += ["", f"[[{path + '.' if path else ''}{k}]]"] + [f"{a} = {value(b)}" for a, b in element.items()]


def dumps(doc: dict, header: str = "") -> str:
    lines = [f"# {line}" for line in header.splitlines()]
    table(doc, "", lines)
    return "\n".join(lines).lstrip("\n") + "\n"
