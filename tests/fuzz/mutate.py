"""Deterministic mutations of TOML files and run files (tests/fuzz/fuzz.py).

Every mutation is a function of a random.Random and its input; the same seed
gives the same inputs on every machine. Each returns (kind, result)."""
import copy

import numpy as np

from pipeline.tomlwrite import Raw, dumps, is_table_array

# Values a hostile or careless user writes, as TOML text.
SPECIAL_NUMBERS = ["nan", "inf", "-inf", "1e300", "-1e300", "0", "-1", "1e-300", "0.0", "-0.0",
                   "9223372036854775807", "-9223372036854775808", "4294967296", "1e15", "1e-15", "2.5"]
# the edges of the types a value is stored in: 32- and 64-bit integers (one past them, and one past what a
# double holds exactly), counts that fit the type but not the memory, subnormal and near-overflow floats
INT_WIDTHS = ["2147483647", "2147483648", "-2147483649", "4294967295", "4294967297", "9007199254740993",
              "9223372036854775807", "1000000000", "1e9", "1e18", "4294967297.0"]
FLOAT_EDGES = ["5e-324", "1e-310", "-1e-310", "2.2250738585072014e-308", "1e-320", "1.7976931348623157e308",
               "1e308", "-1e308"]
WRONG_TYPES = ['"text"', "true", "[1, 2]", "{ a = 1 }", "[]", '""', "[[1, 2], [3]]", '["x", "y"]']


# ---- structural mutations of a parsed TOML document ----

def _leaves(doc):
    """Every (container, key) of the document: values, tables and table arrays' elements' keys."""
    out = []

    def walk(t):
        for k, v in list(t.items()):
            out.append((t, k))
            if isinstance(v, dict):
                walk(v)
            elif is_table_array(v):
                for e in v:
                    walk(e)

    walk(doc)
    return out


def _misspell(rng, key):
    if len(key) < 2:
        return key + "x"
    i = rng.randrange(len(key) - 1)
    return key[:i] + key[i + 1] + key[i] + key[i + 2:] if key[i] != key[i + 1] else key + "s"


def mutate_toml(rng, text):
    """One mutation of a TOML text: structural (parsed, changed, written back)
    or textual (bytes cut or inserted). Returns (kind, new text)."""
    import tomllib

    doc = tomllib.loads(text)
    leaves = _leaves(doc)
    kinds = ["delete", "special", "wrong_type", "scale", "unknown_key", "long_key", "array_size",
             "truncate", "garbage", "duplicate_line", "int_width", "float_edge"]
    kind = rng.choice(kinds)
    if kind in ("int_width", "float_edge"):  # a number of the matching type (any number when there is none)
        doc = copy.deepcopy(doc)
        slots = _leaves(doc) + [(c[k], i) for c, k in _leaves(doc) if isinstance(c[k], list) and not is_table_array(c[k])
                                for i in range(len(c[k]))]  # an element of an array of numbers too
        numbers = [(c, k) for c, k in slots if isinstance(c[k], (int, float)) and not isinstance(c[k], bool)]
        typed = [(c, k) for c, k in numbers if isinstance(c[k], int) == (kind == "int_width")]
        if typed or numbers:
            container, key = rng.choice(typed or numbers)
            container[key] = Raw(rng.choice(INT_WIDTHS if kind == "int_width" else FLOAT_EDGES))
            return kind, dumps(doc)
        kind = "special"
    if kind in ("truncate", "garbage", "duplicate_line") or not leaves:
        lines = text.splitlines(keepends=True)
        if kind == "truncate":
            return kind, text[: rng.randrange(len(text))]
        if kind == "garbage":
            i = rng.randrange(len(text))
            junk = rng.choice(["\x00", "\xff\xfe", "[[", "]]", "=", '"', "\\u12", "\n[x\n", "= = =", "\t#"])
            return kind, text[:i] + junk + text[i:]
        line = rng.choice(lines) if lines else ""
        return kind, text + ("\n" if not text.endswith("\n") else "") + line
    doc = copy.deepcopy(doc)
    container, key = rng.choice(_leaves(doc))
    value = container[key]
    if kind == "delete":
        del container[key]
    elif kind == "special":
        container[key] = Raw(rng.choice(SPECIAL_NUMBERS))
    elif kind == "wrong_type":
        container[key] = Raw(rng.choice(WRONG_TYPES))
    elif kind == "scale":
        f = rng.choice([1e6, 1e-6, -1.0, 1e12, 0.5])
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            container[key] = Raw(rng.choice(SPECIAL_NUMBERS))
        else:
            container[key] = value * f if isinstance(value, float) else int(value * f) if abs(value * f) < 2**62 else value * f
    elif kind == "unknown_key":
        container[_misspell(rng, key)] = value
        del container[key]
    elif kind == "long_key":
        container["k" * rng.choice([100, 100000])] = 1
    elif kind == "array_size":
        if isinstance(value, list) and value:
            container[key] = rng.choice([[], value[:1], value * 200])
        else:
            container[key] = [value] * rng.choice([0, 3])
    return kind, dumps(doc)


# ---- run-file mutations (h5py) ----
# Each names the dataset it touches; the oracle in fuzz.py decides which
# consumers must refuse the result.

def float_datasets(f):
    names = []
    f.visititems(lambda n, o: names.append(n) if hasattr(o, "dtype") and o.dtype.kind == "f" and o.size > 0 else None)
    return sorted(names)


def all_datasets(f):
    names = []
    f.visititems(lambda n, o: names.append(n) if hasattr(o, "dtype") else None)
    return sorted(names)


# what a root attribute becomes: text, an array, an integer or float where the other was, non-finite, huge
ROOT_ATTR_DAMAGE = ["delete", "text", "", [1.0, 2.0], [3], float("nan"), float("inf"), -1, 0, 2.5, 1e300, 2**40,
                    np.int32(7), np.float32(0.5)]


def mutate_run(rng, f):
    """Mutates an open h5py File in place. Returns (kind, dataset, where):
    where = "last" when the change is in the last snapshot's rows, "all" when
    it reaches every row (or the file's structure), "some" otherwise."""
    kind = rng.choice(["nan", "inf", "negative", "huge", "shorter", "empty", "delete", "int_type",
                       "reverse_time", "repeat_time", "bad_contact", "truncate_file", "root_attr"])
    if kind == "truncate_file":
        return kind, "", "all"
    if kind == "root_attr":  # one of the root's attributes (named "@name") deleted or of another type or value
        name = rng.choice(sorted(f.attrs))
        value = rng.choice(ROOT_ATTR_DAMAGE)
        if value == "delete":
            del f.attrs[name]
            return kind, "@" + name, "deleted"
        f.attrs[name] = np.array(value) if isinstance(value, list) else value
        return kind, "@" + name, "all"
    floats = float_datasets(f)
    if kind in ("reverse_time", "repeat_time"):
        name = rng.choice([n for n in ("snapshots/time", "series/time") if n in f])
        t = f[name][:]
        if len(t) < 2:
            return kind, name, "all"
        i = rng.randrange(1, len(t))
        t[i] = t[i - 1] - (1.0 if kind == "reverse_time" else 0.0)
        f[name][...] = t
        return kind, name, "all"
    if kind == "bad_contact":
        name = rng.choice(["contacts/i", "contacts/j"])
        if name not in f or f[name].size == 0:
            return kind, name, "none"
        v = f[name][:]
        k = rng.randrange(len(v))
        v[k] = rng.choice([-100000, 10**9, v[k] if name == "contacts/j" else -1])
        if name == "contacts/j":
            v[k] = f["contacts/i"][k]  # a self-contact
        f[name][...] = v
        starts = f["snapshots/contact_start"][:]
        last = k >= starts[-2] if len(starts) > 1 else True
        return kind, name, "last" if last else "some"
    if kind in ("shorter", "empty", "delete", "int_type"):
        name = rng.choice(all_datasets(f))
        data = f[name][()]
        if kind in ("shorter", "empty") and data.size == 0:
            return kind, name, "none"  # nothing to take away
        attrs = dict(f[name].attrs)
        del f[name]
        if kind == "delete":
            return kind, name, "all"
        data = np.asarray(data).reshape(-1) if np.ndim(data) == 0 and kind in ("shorter", "empty") else data
        if kind == "shorter":
            data = data[:-1] if len(data) > 1 else data[:0]
        elif kind == "empty":
            data = data[:0]
        elif kind == "int_type":  # integers standing in for floats, floats for integers, integers for text
            if data.dtype.kind == "f":
                data = np.round(np.nan_to_num(data)).astype(np.int64)
            elif data.dtype.kind in "iub":
                data = data.astype(np.float64)
            else:
                data = np.arange(np.size(data), dtype=np.int64).reshape(np.shape(data))
        f.create_dataset(name, data=data)
        for k, v in attrs.items():
            f[name].attrs[k] = v
        return kind, name, "all"
    name = rng.choice(floats)
    d = f[name]
    flat = d[...].reshape(-1)
    per_row = max(1, flat.size // max(1, d.shape[0])) if d.ndim else 1
    row = rng.randrange(d.shape[0]) if d.ndim else 0
    if rng.random() < 0.5 and d.ndim:
        row = d.shape[0] - 1  # the last row: what every consumer of a snapshot reads
    k = row * per_row + rng.randrange(per_row)
    flat[k] = {"nan": np.nan, "inf": np.inf, "negative": -abs(flat[k]) - 1.0, "huge": 1e300}[kind]
    d[...] = flat.reshape(d.shape)
    rows = d.shape[0] if d.ndim else 1
    return kind, name, "last" if row == rows - 1 else "some"
