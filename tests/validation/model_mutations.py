"""Seeded mutations of model files, for the fuzzing tests of the command line.

:func:`mutated_files` turns the example files and the built-in models into mutants, one or two
changes each, drawn from a :class:`random.Random` of a given seed (the same seed gives the same
files on every machine, so a failure reproduces). The bases include small models of the 3D and control
features (:func:`feature_texts`: controllers, sensors, drivers, spatial beams and loops). Changes of the
data (through TOML) replace a value by an extreme number, a wrong type, a huge exponent, an unknown
name or a load with a pole, delete a key or a table, misspell a key or a name it refers to, or rename a part, a sensor or a
controller state after a result column; changes of the text duplicate a table, truncate the file, flip or insert random
bytes. :func:`runnable_mutant` keeps the structure of a model (shape functions, expressions) and
changes only numbers and a few keys, with a short end time, for ``flexkane run``.
"""

from __future__ import annotations

import copy
import math
import pathlib
import random
import re
import tomllib

import tomli_w

from flexkane.builtin import builtin_text

ROOT = pathlib.Path(__file__).resolve().parents[2]

#: Numbers at the edges: zero, signs, the extremes of floating point, integers beyond 64 bits.
EXTREME_NUMBERS = (0, 0.0, -0.0, -1, 1, 2, 41, 200, 201, 10**6, 10**15, 10**16, 2**63, -(2**63), 10**30,
                   1e-320, 5e-324, -5e-324, 1e-300, 1e-12, 1e12, 1e300, -1e300, 1.7976931348623157e308,
                   math.inf, -math.inf, math.nan, 0.5, 2.5, -3.7)
#: Values of a wrong type for almost every field.
WRONG_TYPES = ("", " ", "abc", "true", "none", "nan", "inf", "-inf", "1e999", "0x10", "1_000", True, False,
               [], [1], [1, 2, 3], ["a", "b"], [[0, 1], [2]], {}, {"x": 1}, {"family": "clamped-free"},
               "🙂", "\x00", "a" * 3000, "1" * 40)
#: Expressions that reach the limits of the expression language (exponents, size, depth, names).
HOSTILE_EXPRESSIONS = ("9**9**9", "2**1000", "(3*t)**50", "(t + sin(t) + cos(t) + exp(t) + t**2 + 1)**100",
                       "((3*t)**100)**100", "exp(1000)", "exp(1e6*t)", "log(0)", "1/0", "sqrt(-1)", "t**-101",
                       "10000000000000000", "1e400", "abs(t - 0.005)", "max(t, 1)", "min(t, 0.01)",
                       "where(t < 0.01, t, 0)", "piecewise(t, t < 0.01, 0.01)", "sin(" * 60 + "t" + ")" * 60,
                       "+".join(f"t*{k}" for k in range(300)), "H_11", "m_link", "q1", "u_pivot", "unknown_name",
                       "__import__('os')", "().__class__", "lambda: 1", "[1 for _ in (1,)]", "t if t else 1",
                       "x", "xi", "t", "pi", "L*", "(", "1e-320", "tan(pi/2)", "(-8)**(1/3)",
                       "20:80:50000", "20:80:100001", "0:1:0", "1:1:1", "a:b:c", "20:80:1e9", "-1:1:3", "1:2:3:4",
                       "0.001/(x - 0.35)**2", "1/sqrt(abs(x - 0.5))", "tan(20*x)",
                       "abs(abs(abs(abs(abs(abs(t - 0.01) - 0.01) - 0.01) - 0.01) - 0.01) - 0.01)",
                       "c1 + sin(c1)", "energy", "x_cm")
#: Names of result columns that a part, a coordinate or a controller state may not take.
COLUMN_NAMES = ("energy", "kinetic", "work", "energy_balance", "x_cm", "p_y", "H_z", "t", "yaw_arm", "e0_bus",
                "x_hub", "tip_link", "sensor_tip", "controller_motor", "effort_shoulder", "q_hinge", "u_pivot_wx")
#: Tables whose keys are names of parts, sensors or controllers, and tables of named controller states.
NAMED_TABLES = ("bodies", "beams", "joints", "loads", "distributed_loads", "springs", "constraints", "sensors",
                "controllers", "states")
#: Names a misspelt or invented key may take.
UNKNOWN_KEYS = ("varry", "n_mode", "EII", "masss", "typ", "parnet", "t_ned", "dt-out", "H_11", "m_link",
                "q_pivot", "u_pivot", "../x", "", " ", "a.b", "ü")
#: Keys whose value decides the size of the symbolic work (shape functions per beam); a run keeps
#: them valid or makes them invalid, never a valid larger value (the documented limits take minutes).
STRUCTURAL_KEYS = ("n_modes", "n_axial", "roots", "samples")
#: Keys of [simulation] whose larger valid values mean a longer run.
DURATION_KEYS = ("t_end", "max_steps")


#: Valid files of the corpus of untrusted model files that mutants start from too.
VALID_CORPUS_FILES = ("sweep_valid.toml", "driver_abs.toml", "driver_where.toml", "driver_piecewise.toml",
                      "torque_power_100.toml")


def base_texts() -> dict[str, str]:
    """Model files to start from: every example file, every built-in model (by name) and the valid
    files of the corpus of untrusted model files (with a [sweep] table, drivers with kinks, powers)."""
    from flexkane.builtin import builtin_names

    texts = {p.stem: p.read_text("utf-8") for p in sorted((ROOT / "examples").glob("*.toml"))}
    texts.update({f"feature:{name}": text for name, text in feature_texts().items()})
    for path in sorted((ROOT / "tests" / "validation" / "untrusted_models").glob("*.toml")):
        text = path.read_text("utf-8")   # valid files of the corpus (sweeps, drivers with kinks, powers)
        if path.name in VALID_CORPUS_FILES:
            texts[f"corpus:{path.stem}"] = text
    for name in builtin_names():
        text = builtin_text(name)
        if text not in texts.values():
            texts[f"builtin:{name}"] = text
    return texts


def feature_texts() -> dict[str, str]:
    """Small models of the 3D and control features, by name: a hinge with a PID controller, a filter
    and point and joint sensors; a free body under an attitude law with integral states; a clamped
    spatial beam with a sensor of every beam kind; the spatial loops of the loop-closure tests (point on
    a line, welded pair, RSSR, slider-crank); the planar PID arm (a driver-free controller chain)."""
    from spatial_control_models import (ATTITUDE, ATTITUDE_PI, HINGE, HINGE_SENSORS, INTEGRAL, PID, SENSED_BEAM,
                                        SPRING)

    texts = {"hinge-pid-sensors": HINGE.replace("{effort}", PID) + HINGE_SENSORS,
             "hinge-spring": HINGE.replace("{effort}", SPRING),
             "attitude-integral": ATTITUDE.replace("{torque}", ATTITUDE_PI) + INTEGRAL,
             "sensed-beam": SENSED_BEAM}
    for path in sorted((ROOT / "tests" / "kane" / "spatial_loops").glob("*.toml")):
        texts[f"loop-{path.stem}"] = path.read_text("utf-8")
    return texts


def _leaves(node, path=()):
    """Every key path below ``node``, tables and lists included, as tuples of keys and indices."""
    items = node.items() if isinstance(node, dict) else enumerate(node) if isinstance(node, list) else ()
    for key, child in items:
        yield path + (key,), child
        yield from _leaves(child, path + (key,))


def _parent(data, path):
    for key in path[:-1]:
        data = data[key]
    return data


def _misspell(rng: random.Random, key: str) -> str:
    i = rng.randrange(max(len(key), 1))
    kind = rng.choice(("drop", "insert", "swap", "case", "invent"))
    if kind == "drop" and len(key) > 1:
        return key[:i] + key[i + 1:]
    if kind == "insert":
        return key[:i] + rng.choice("aeiou_x1") + key[i:]
    if kind == "swap" and i + 1 < len(key):
        return key[:i] + key[i + 1] + key[i] + key[i + 2:]
    if kind == "case":
        return key.swapcase()
    return rng.choice(UNKNOWN_KEYS)


def _change_data(rng: random.Random, data: dict) -> str:
    """Apply one change to the parsed file ``data`` in place; return its kind."""
    entries = list(_leaves(data))
    if not entries:
        data[rng.choice(UNKNOWN_KEYS) or "x"] = 1
        return "invent"
    path, value = rng.choice(entries)
    parent, key = _parent(data, path), path[-1]
    kind = rng.choice(("number", "number", "type", "expression", "power", "delete", "rename", "name", "column",
                       "typo"))
    named = [p for p, _ in entries if len(p) >= 2 and p[-2] in NAMED_TABLES and isinstance(p[-1], str)]
    if kind == "column" and named:   # a part, a controller state or a sensor named like a result column
        path = rng.choice(named)
        parent = _parent(data, path)
        parent[rng.choice(COLUMN_NAMES)] = parent.pop(path[-1])
    elif kind == "number":
        parent[key] = rng.choice(EXTREME_NUMBERS)
    elif kind == "type":
        parent[key] = copy.deepcopy(rng.choice(WRONG_TYPES))
    elif kind == "expression":
        parent[key] = rng.choice(HOSTILE_EXPRESSIONS)
    elif kind == "power":   # a huge exponent on a value the file has
        parent[key] = f"({value})**{rng.choice((2, 50, 99, 100, 101, 400, 10**6, '9**9', '-101', '0.5'))}"
    elif kind == "delete":
        del parent[key]
    elif kind == "rename" and isinstance(key, str):
        parent[_misspell(rng, key)] = parent.pop(key)
    elif kind == "typo":   # a misspelt reference, often in a list of names (dependent speeds, coordinates)
        names = [(p, v) for p, v in entries if isinstance(v, str) and v.isidentifier()]
        listed = [(p, v) for p, v in names if isinstance(p[-1], int)]
        if names:
            path, value = rng.choice(listed if listed and rng.random() < 0.5 else names)
            _parent(data, path)[path[-1]] = _misspell(rng, value)
    elif kind == "name" and isinstance(value, str):   # an unknown or generated name inside an expression
        parent[key] = f"{value} + {rng.choice(('nope', 'H_11', 'm_rod', 'q_pivot', 't', 'xi', 'x'))}"
    else:
        parent[key] = rng.choice(EXTREME_NUMBERS)
    return kind


_TABLE = re.compile(r"^\[[^\]\n]+\]\s*$", re.MULTILINE)


def _change_text(rng: random.Random, text: str) -> bytes:
    """Apply one change to the text of a file; return its bytes (not always UTF-8, not always TOML)."""
    kind = rng.choice(("duplicate", "truncate", "bytes", "flip", "line", "repeat"))
    raw = text.encode("utf-8")
    if kind == "duplicate":   # a table (or its header) twice
        tables = list(_TABLE.finditer(text))
        if tables:
            start = rng.choice(tables).start()
            stop = min((m.start() for m in tables if m.start() > start), default=len(text))
            block = text[start:stop] if rng.random() < 0.7 else text[start:text.index("\n", start) + 1]
            return (text + "\n" + block).encode("utf-8")
    if kind == "truncate":
        return raw[:rng.randrange(len(raw) + 1)]
    if kind == "bytes":
        at = rng.randrange(len(raw) + 1)
        return raw[:at] + bytes(rng.randrange(256) for _ in range(rng.randint(1, 16))) + raw[at:]
    if kind == "flip":
        data = bytearray(raw)
        for _ in range(rng.randint(1, 4)):
            if data:
                data[rng.randrange(len(data))] ^= 1 << rng.randrange(8)
        return bytes(data)
    if kind == "line":   # one line deleted
        lines = text.splitlines(keepends=True)
        if lines:
            del lines[rng.randrange(len(lines))]
        return "".join(lines).encode("utf-8")
    lines = text.splitlines(keepends=True)   # one line repeated: a duplicated key
    if lines:
        at = rng.randrange(len(lines))
        lines.insert(at, lines[at])
    return "".join(lines).encode("utf-8")


#: Values given on the command line with --set KEY=VALUE.
SET_VALUES = ("0", "-1", "1e999", "nan", "inf", "5e-324", "1e300", "abc", "", "[1, 2]", "[1, 2", "[[0, 1]]",
              "{a = 1}", "true", "'x'", "9**9**9", "(3*t)**50", "H_11", "u_pivot", "sin(t)", "1/0", "41", "200")


def mutated_arguments(rng: random.Random, text: str) -> list[str]:
    """Options of ``flexkane check`` that change the model: --set of a key path of ``text`` (or an
    unknown one) to a hostile value, or --n-modes."""
    if rng.random() < 0.3:
        return ["--n-modes", str(rng.choice((0, -1, 1, 2, 40, 41, 200, 10**20, "x", "2.5")))]
    try:
        paths = [p for p, _ in _leaves(tomllib.loads(text)) if p[0] != "sweep"]
    except tomllib.TOMLDecodeError:
        paths = []
    path = rng.choice(paths) if paths and rng.random() < 0.8 else (rng.choice(UNKNOWN_KEYS),)
    key = "".join(f"[{k}]" if isinstance(k, int) else f".{k}" for k in path).lstrip(".")
    if rng.random() < 0.3:   # a bare parameter or coordinate name
        key = str(path[-1])
    return ["--set", f"{key}={rng.choice(SET_VALUES)}"]


def mutated_file(rng: random.Random, texts: dict[str, str]) -> tuple[str, bytes, list[str]]:
    """One mutant of one of ``texts``: (a description, the file's bytes, options of check); one in
    five also changes values with command-line options."""
    name = rng.choice(sorted(texts))
    text = texts[name]
    kinds = []
    data = tomllib.loads(text)
    for _ in range(rng.randint(1, 2)):
        if rng.random() < 0.75:
            kinds.append(_change_data(rng, data))
        else:
            kinds.append("text")
            break
    try:
        body = tomli_w.dumps(data).encode("utf-8") if kinds[0] != "text" else text.encode("utf-8")
    except (TypeError, ValueError):   # e.g. a value TOML cannot write: the text itself is changed
        body = text.encode("utf-8")
        kinds.append("text")
    if kinds[-1] == "text":
        body = _change_text(rng, body.decode("utf-8"))
    options = mutated_arguments(rng, text) if rng.random() < 0.2 else []
    return f"{name}: {', '.join(kinds)} {' '.join(options)}", body, options


def mutated_files(seed: int, count: int) -> list[tuple[str, bytes, list[str]]]:
    """``count`` mutants of the example files and built-in models, the same for the same seed."""
    rng = random.Random(seed)
    texts = base_texts()
    return [mutated_file(rng, texts) for _ in range(count)]


def runnable_mutant(rng: random.Random, text: str, t_end: float) -> tuple[str, str]:
    """A mutant of ``text`` for ``flexkane run``: end time ``t_end`` [s] and one changed number or
    key, structure and run length kept bounded (see :data:`STRUCTURAL_KEYS`, :data:`DURATION_KEYS`)."""
    data = tomllib.loads(text)
    data.pop("sweep", None)
    simulation = data.setdefault("simulation", {})
    simulation["t_end"] = t_end
    simulation["dt_out"] = t_end / 10
    simulation["max_steps"] = 100_000
    entries = [(p, v) for p, v in _leaves(data)
               if not isinstance(v, (dict, list)) and not isinstance(v, bool) and p[0] != "name"]
    if rng.random() < 0.1:   # a name that is not a folder name (the default output folder is out/NAME)
        data["name"] = rng.choice(("../../ESCAPED", "out/../../ESCAPED", "..", ".", "", "a/b", "x" * 300, "ä b:c*?"))
        return f"name: {data['name']!r}", tomli_w.dumps(data)
    path, value = rng.choice(entries)
    parent, key = _parent(data, path), path[-1]
    kind = rng.choice(("number", "number", "number", "type", "delete", "rename"))
    if key in STRUCTURAL_KEYS or key in DURATION_KEYS or key == "dt_out":
        kind = "invalid"
        parent[key] = rng.choice((0, -1, 2.5, "abc", 10**18, -math.inf, math.nan))
    elif kind == "number":
        parent[key] = rng.choice((0, 0.0, -1, 1e-300, 1e-12, 1e-6, 1e6, 1e12, 1e300, -1e300, 5e-324,
                                  math.inf, math.nan))
    elif kind == "type":
        parent[key] = copy.deepcopy(rng.choice(WRONG_TYPES[:12]))
    elif kind == "delete":
        del parent[key]
    elif isinstance(key, str):
        parent[_misspell(rng, key)] = parent.pop(key)
    return f"{'.'.join(map(str, path))}: {kind} ({value!r})", tomli_w.dumps(data)
