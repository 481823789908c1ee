"""The one TOML writer (Python reads TOML with tomllib but has no writer):
the scenes, overlays and settings the pipeline, `make validate`, `make
bench-compare` and the tests' fuzzer generate.

    dumps({"name": "x", "contact": {"kn": 1e6, "wall": {"friction": 0.3}}, "body": [{...}, {...}]},
          header="what this file is")

Top-level values first, then tables ([a], [a.b] for nested ones), then arrays
of tables ([[body]]); a table inside an array element is written inline.
Numbers as Python writes them (repr: a float keeps every digit; nan, inf,
-inf as TOML spells them); a key that is not a bare key is quoted; `Raw(text)`
is written as given (the fuzzer's special numbers and wrong types).
"""
import math
import numbers


class Raw:
    """A value written as given, not as TOML would spell a Python value."""

    def __init__(self, text: str):
        self.text = text


def string(s: str) -> str:
    """A TOML basic string: backslash, quote and control characters escaped."""
    out = []
    for c in s:
        if c in '\\"':
            out.append("\\" + c)
        elif ord(c) < 0x20 or ord(c) == 0x7F:
            out.append({"\n": "\\n", "\t": "\\t", "\r": "\\r"}.get(c, f"\\u{ord(c):04X}"))
        else:
            out.append(c)
    return '"' + "".join(out) + '"'


def key(k) -> str:
    k = str(k)
    return k if k and all(c.isascii() and (c.isalnum() or c in "_-") for c in k) else string(k)


def value(v) -> str:
    if isinstance(v, Raw):
        return v.text
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, numbers.Integral):
        return str(int(v))
    if isinstance(v, numbers.Real):
        f = float(v)
        return "nan" if math.isnan(f) else repr(f)  # (repr gives inf and -inf as TOML spells them)
    if isinstance(v, str):
        return string(v)
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{ " + ", ".join(f"{key(k)} = {value(x)}" for k, x in v.items()) + " }"
    raise ValueError(f"cannot write {v!r} as TOML")


def is_table_array(v) -> bool:
    return isinstance(v, list) and bool(v) and all(isinstance(x, dict) for x in v)


def table(doc: dict, path: str, lines: list) -> None:
    plain = {k: v for k, v in doc.items() if not isinstance(v, dict) and not is_table_array(v)}
    if path and (plain or not any(isinstance(v, dict) for v in doc.values())):
        lines += ["", f"[{path}]"]
    lines += [f"{key(k)} = {value(v)}" for k, v in plain.items()]
    for k, v in doc.items():
        if isinstance(v, dict):
            table(v, f"{path}.{key(k)}" if path else key(k), lines)
    for k, v in doc.items():
        if is_table_array(v):
            for element in v:
                lines += ["", f"[[{path + '.' if path else ''}{key(k)}]]"]
                lines += [f"{key(a)} = {value(b)}" for a, b in element.items()]


def dumps(doc: dict, header: str = "") -> str:
    lines = [f"# {line}" for line in header.splitlines()]
    table(doc, "", lines)
    return "\n".join(lines).lstrip("\n") + "\n"
