"""Bad input never gets past validation: properties over scenes, ``--set``, ``--sweep`` and saved sweep CSVs.

The contract for every rejected input: exit status 2; stderr is one paragraph (one line) starting
``contin: error:`` that names what is wrong (the field ``section.key`` with the expected type or the
allowed range, the file, the line and column of a damaged CSV row); no traceback; and no output: after
``contin trace --out DIR`` DIR holds no new file, and the CSV of ``contin classify --sweep --csv PATH``
is left byte for byte as it was.

Hypothesis draws the bad input (derandomized: CI sees the same examples on every run).  The models
are guarded: a scene that passed validation reaches a stand-in that raises :class:`Reached` instead of
computing, so a bad value that slips through fails the test at once (and costs no continuation run).
A few subprocess runs check the same contract at the process level.
"""

from __future__ import annotations

import contextlib
import csv
import dataclasses
import datetime
import importlib
import importlib.util
import io
import math
import os
import signal
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Any
from unittest import mock

import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from contin.app import cli
from contin.app.scene import Classification, Field, SceneModel, Schema, TraceResult, can_classify, format_toml_value
from contin.app.sweep import SweepError, read_sweep_csv

MODELS = ("shell", "bratu", "truss")
_REAL_LOAD = cli.load_model
#: Hypothesis settings of every property here: reproducible, no deadline, few enough examples for ~30 s.
PROPERTY = settings(max_examples=75, deadline=None, derandomize=True, database=None,
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])


# ---- guarded models ---------------------------------------------------------------------------------------
class Reached(BaseException):
    """A scene got past validation to the model (a BaseException: the command line does not catch it)."""

    def __init__(self, scene: dict[str, dict[str, Any]]) -> None:
        super().__init__(f"the model was run with {scene!r}")
        self.scene = scene


class Guarded:
    """A registered model with its schema, whose ``run`` and ``classify`` raise :class:`Reached`."""

    def __init__(self, runner: Any) -> None:
        self.name, self.description, self.schema = runner.name, runner.description, runner.schema
        self.can_classify = can_classify(runner)

    def run(self, scene: dict, progress: bool) -> TraceResult:
        raise Reached(scene)

    def classify(self, scene: dict, progress: bool) -> Classification:
        raise Reached(scene)


_GUARDED: dict[str, Guarded] = {}


def guarded_load(name: str) -> Guarded:
    if name not in _GUARDED:
        _GUARDED[name] = Guarded(_REAL_LOAD(name))
    return _GUARDED[name]


def call(*argv: str, load: Any = guarded_load) -> tuple[int, str, str]:
    """``contin ARGV`` in this process, with ``load`` as the model registry: (exit status, stdout, stderr)."""
    out, err = io.StringIO(), io.StringIO()
    with mock.patch.object(cli, "load_model", load), contextlib.redirect_stdout(out), \
            contextlib.redirect_stderr(err):
        code = cli.main(list(argv))
    return code, out.getvalue(), err.getvalue()


def assert_rejected(code: int, out: str, err: str, *needles: str) -> None:
    """Exit status 2, nothing on stdout, one ``contin: error:`` paragraph holding every needle, no traceback."""
    assert code == 2, (code, err)
    assert out == ""
    assert err.startswith("contin: error:") and err.endswith("\n") and err.count("\n") == 1, err
    assert "Traceback" not in err
    for needle in needles:
        assert needle in err, (needle, err)


def files_in(path: Path) -> list[str]:
    """Every entry of ``path`` (temporaries included); [] when it does not exist."""
    return sorted(os.listdir(path)) if path.exists() else []


def schema_of(model: str) -> Schema:
    return guarded_load(model).schema


FIELDS = [(m, sec, key, f) for m in MODELS for sec, keys in schema_of(m).sections.items() for key, f in keys.items()]
EXPECTED_TYPE = {bool: "a boolean", int: "an integer", float: "a number", str: "a string"}


# ---- TOML values ------------------------------------------------------------------------------------------
def toml_literal(value: Any) -> str:
    """``value`` written as a TOML value (strings as basic strings, bare words are passed as str subclasses)."""
    if isinstance(value, BareWord):
        return value.text
    if isinstance(value, list):
        return "[" + ", ".join(toml_literal(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k} = {toml_literal(v)}" for k, v in value.items()) + "}"
    if isinstance(value, (datetime.date, datetime.time)):
        return value.isoformat()
    # scalars as the toolkit writes them (strings as basic strings; no control characters are drawn)
    return format_toml_value(value)


@dataclasses.dataclass(frozen=True)
class BareWord:
    """A word given unquoted (``--set load.kind=plate``): not TOML, so it is read as a string."""

    text: str


texts = st.text(st.characters(exclude_categories=("Cc", "Cs")), max_size=12)
words = st.from_regex(r"[A-Za-z][A-Za-z_]{0,8}", fullmatch=True).filter(
    lambda w: w not in ("true", "false", "nan", "inf")).map(BareWord)
small_ints = st.integers(-10**6, 10**6)
finite_floats = st.floats(allow_nan=False, allow_infinity=False)
arrays = st.lists(small_ints | texts, max_size=3)
tables = st.dictionaries(st.from_regex(r"[a-z]{1,5}", fullmatch=True), small_ints, max_size=2)
dates = st.dates(min_value=datetime.date(1000, 1, 1)) | st.times()
WRONG_TYPE = {
    float: st.booleans() | texts | words | arrays | tables | dates,
    int: finite_floats | st.booleans() | texts | words | arrays | dates,
    bool: small_ints | finite_floats | texts | words | arrays,
    str: small_ints | finite_floats | st.booleans() | arrays | tables | dates,
}


def scene_args(tmp: Path, model: str, section: str, key: str, literal: str, via_file: bool) -> list[str]:
    """Arguments that give ``section.key = literal`` by ``--set`` or by a scene file in ``tmp``."""
    if via_file:
        path = tmp / "scene.toml"
        path.write_text(f"[{section}]\n{key} = {literal}\n", encoding="utf-8")
        return ["-m", model, str(path)]
    return ["-m", model, f"--set={section}.{key}={literal}"]


def check_trace_rejects(args: list[str], *needles: str) -> str:
    """``contin trace ARGS --out DIR`` is rejected with the needles and leaves DIR (with a file in it) as it was."""
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "out"
        out.mkdir()
        (out / "keep.txt").write_text("kept")
        code, stdout, err = call("trace", "-q", *args, "--out", str(out))
        assert_rejected(code, stdout, err, *needles)
        assert files_in(out) == ["keep.txt"] and (out / "keep.txt").read_text() == "kept"
    return err


# ---- scene values: types, ranges, non-finite numbers, unknown names -----------------------------------------
@PROPERTY
@given(st.sampled_from(FIELDS), st.data(), st.booleans())
def test_a_wrong_type_names_the_field_and_the_expected_type(field, data, via_file):
    """Any value of another type, by --set or in a file: the field, the expected type, the allowed values."""
    model, section, key, fld = field
    value = data.draw(WRONG_TYPE[fld.type], label="value")
    if via_file and isinstance(value, BareWord):
        value = value.text  # only the command line takes a bare word: in a file a string is quoted
    with tempfile.TemporaryDirectory() as tmp:
        args = scene_args(Path(tmp), model, section, key, toml_literal(value), via_file)
        where = args[-1] if via_file else "(from --set "
        check_trace_rejects(args, f"{section}.{key} = ", "has the wrong type", f"expected {EXPECTED_TYPE[fld.type]}",
                            f"allowed: {fld.allowed}", where)


def _fits(fld: Field, value: Any) -> bool:
    """Whether a value of the field's type is in its allowed range (integers: also within 64 bits)."""
    if fld.type is int and not -2**63 <= value < 2**63:
        return False
    return fld.check is None or bool(fld.check(value))


RANGED = [f for f in FIELDS if f[3].check is not None]
OUT_OF_RANGE = {
    int: st.integers() | st.integers(min_value=2**62) | st.integers(max_value=-2**62) | st.integers(-20, 20),
    float: finite_floats | st.floats(-2.0, 2.0),
    str: texts | words.map(lambda w: w.text),
}


@PROPERTY
@given(st.sampled_from(RANGED), st.data(), st.booleans())
def test_an_out_of_range_value_names_the_field_and_the_allowed_range(field, data, via_file):
    """Any value outside a field's range (integers also beyond 64 bits): the field and the allowed range."""
    model, section, key, fld = field
    value = data.draw(OUT_OF_RANGE[fld.type].filter(lambda v: not _fits(fld, v)), label="value")
    with tempfile.TemporaryDirectory() as tmp:
        args = scene_args(Path(tmp), model, section, key, toml_literal(value), via_file)
        check_trace_rejects(args, f"{section}.{key} = ", "is out of range", f"allowed: {fld.allowed}")


NON_FINITE = ["nan", "+nan", "-nan", "inf", "+inf", "-inf", "1e999", "-1e999", "1" + "0" * 400, "-1" + "0" * 330]
HUGE_INTS = [str(2**63), str(-2**63 - 1), "99999999999999999999999999999", "1" + "0" * 400]


@PROPERTY
@given(st.sampled_from([f for f in FIELDS if f[3].type in (int, float)]), st.data(), st.booleans())
def test_nan_infinity_and_overflowing_numbers_never_pass(field, data, via_file):
    """nan, inf, 1e999 and integers beyond the float or 64-bit range are refused for every numeric field."""
    model, section, key, fld = field
    literal = data.draw(st.sampled_from(NON_FINITE + (HUGE_INTS if fld.type is int else [])), label="literal")
    with tempfile.TemporaryDirectory() as tmp:
        args = scene_args(Path(tmp), model, section, key, literal, via_file)
        if fld.type is float:
            check_trace_rejects(args, f"{section}.{key}", "expected a finite number", f"allowed: {fld.allowed}")
        elif literal.lstrip("+-").isdigit():
            check_trace_rejects(args, f"{section}.{key}", "is out of range", f"allowed: {fld.allowed}")
        else:
            check_trace_rejects(args, f"{section}.{key}", "expected an integer", f"allowed: {fld.allowed}")


names = st.from_regex(r"[A-Za-z_][A-Za-z0-9_]{0,12}", fullmatch=True)


@PROPERTY
@given(st.sampled_from(MODELS), names, names, st.booleans(), st.booleans())
def test_unknown_sections_and_keys_are_named_with_what_is_allowed(model, section, key, known_section, via_file):
    """An unknown section lists the model's sections; an unknown key lists its section's keys."""
    sections = schema_of(model).sections
    if known_section:
        section = sorted(sections)[len(key) % len(sections)]
        assume(key not in sections[section])
    else:
        assume(section not in sections)
    with tempfile.TemporaryDirectory() as tmp:
        args = scene_args(Path(tmp), model, section, key, "1", via_file)
        if known_section:
            check_trace_rejects(args, f"unknown scene key {section}.{key}", f"[{section}] allows: "
                                + ", ".join(sections[section]))
        else:
            check_trace_rejects(args, f"unknown scene section [{section}]", "allowed sections: "
                                + ", ".join(f"[{s}]" for s in sections))


@PROPERTY
@given(st.sampled_from([m for m in MODELS if "ds_max" in schema_of(m).sections["continuation"]]),
       st.floats(1e-6, 10.0), st.floats(1.0 + 1e-9, 1e6))
def test_ds_above_ds_max_is_refused_with_the_rule(model, ds_max, factor):
    """Fields valid one by one but breaking a rule together: both fields and the rule are named."""
    args = ["-m", model, f"--set=continuation.ds_max={ds_max!r}", f"--set=continuation.ds={ds_max * factor!r}"]
    check_trace_rejects(args, "continuation.ds = ", "continuation.ds_max = ", "not allowed together",
                        "allowed: continuation.ds <= continuation.ds_max")


# ---- --set syntax -----------------------------------------------------------------------------------------
word = st.from_regex(r"[A-Za-z0-9_]{1,8}", fullmatch=True)
value_text = st.from_regex(r"[A-Za-z0-9_.+-]{1,8}", fullmatch=True)
MALFORMED_SET = st.one_of(
    st.from_regex(r"[A-Za-z0-9_.+-]{1,16}", fullmatch=True),                      # no '='
    st.builds("{}={}".format, word, value_text),                                   # no section
    st.builds(".{}={}".format, word, value_text),                                  # empty section
    st.builds("{}.={}".format, word, value_text),                                  # empty key
    st.builds("{}.{}.{}={}".format, word, word, word, value_text),                 # a dotted key
    st.builds("{}.{}={}".format, word, word, st.sampled_from(["", " ", "   "])),   # no value
)


@PROPERTY
@given(MALFORMED_SET.filter(lambda t: not ("=" in t and "." in t.partition("=")[0]
                                           and t.partition("=")[0].count(".") == 1
                                           and all(t.partition("=")[0].split("."))
                                           and t.partition("=")[2].strip())))
def test_a_malformed_set_shows_the_argument_and_the_form(text):
    """Without the form section.key=value, the argument is shown as given and the form is named."""
    check_trace_rejects(["-m", "bratu", f"--set={text}"], "bad --set argument", "section.key=value",
                        " ".join(repr(text).split()))  # the message is one paragraph: its whitespace is collapsed


@pytest.mark.parametrize("args, needles", [
    (["--set", "shell.h=nan"], ["shell.h = nan", "expected a finite number", "a float > 0"]),
    (["--set", "shell.h=inf"], ["shell.h = inf", "expected a finite number", "a float > 0"]),
    (["--set", "shell.phi_hat=1e999"], ["shell.phi_hat = inf", "expected a finite number", "a float in (0, 1.5708)"]),
    (["--set", "shell.N=99999999999999999999999999999"], ["shell.N", "out of range", "an integer >= 10 and <= 20000"]),
    (["--set", "shell.N=20001"], ["shell.N = 20001", "out of range", "<= 20000"]),
    (["--set", "shell.N=100000"], ["shell.N = 100000", "out of range", "<= 20000"]),
    (["--set", "shell.N=-5"], ["shell.N = -5", "out of range", "an integer >= 10"]),
    (["--set", "shell.N=9"], ["shell.N = 9", "out of range", "an integer >= 10"]),
    (["--set", "shell.N=30.0"], ["shell.N = 30.0", "expected an integer, got a float"]),
    (["--set", "shell.N=3e1"], ["shell.N = 30.0", "expected an integer, got a float"]),
    (["--set", "output.figure=True"], ["output.figure", "expected a boolean (true or false), got a string"]),
    (["--set", "output.figure=1"], ["output.figure = 1", "expected a boolean (true or false), got an integer"]),
    (["--set", "shell.h=true"], ["shell.h = true", "expected a number, got a boolean"]),
    (["--set", "shell.h=1979-05-27"], ["shell.h = 1979-05-27", "expected a number, got a date"]),
    (["--set", "shell.h=[0.01]"], ["shell.h = [0.01]", "expected a number, got an array"]),
    (["--set", "load.kind=Point"], ["load.kind", "out of range", '"point", "ring", "sphere", "plate"']),
    (["--set", "continuation.max_steps=1000001"], ["continuation.max_steps", "an integer in [1, 1000000]"]),
    (["--set", "continuation.ds=0.5"], ["continuation.ds = 0.5", "continuation.ds <= continuation.ds_max"]),
    (["--set", "shell.h"], ["'shell.h'", "section.key=value"]),
    (["--set", "nosuch.h=1"], ["[nosuch]", "[shell], [load], [continuation], [contact], [output]"]),
    (["--set", "shell.h=" + "[" * 3000 + "]" * 3000], ["shell.h", "nested too deeply"]),
    (["-m", "bratu", "--set", "model.n=1000001"], ["model.n", "an integer >= 2 and <= 1000000"]),
    (["-m", "bratu", "--set", "model.n=" + str(2**63 - 1)], ["model.n", "an integer >= 2 and <= 1000000"]),
    (["-m", "truss", "--set", "model.b=1e308", "--set", "model.a=1e-308"], ["model.b / model.a < 2.4"]),
    # a flat plate under volume control divided by its zero reference volume (an internal error before)
    (["--set", "load.kind=pressure", "--set", "shell.geometry=plate", "--set", "shell.boundary=clamped"],
     ["shell.geometry = \"plate\"", "load.control = \"force\" for a pressure", "encloses none"]),
])
def test_set_values_from_the_issue(args, needles):
    """The cases of the issue, by trace and by a classify sweep (which writes no CSV for them)."""
    check_trace_rejects(args, *needles)
    with tempfile.TemporaryDirectory() as tmp:  # classify resolves the scene the same way
        code, out, err = call("classify", *args, "--sweep", "shell.pole_ratio=0.5,1", "--csv", f"{tmp}/s.csv")
        assert_rejected(code, out, err)
        assert files_in(Path(tmp)) == []


# the numbers of the mesh rule by hand: ceil(4 (pi/2 - 0.8) / sqrt(h/R)) with R = 1
@pytest.mark.parametrize("args, needles, absent", [
    (["--set", "shell.N=20"], ["this shell needs shell.N >= 22", "shell.N = 20 puts 3.7 nodes"], []),
    (["--set", "shell.N=40", "--set", "shell.h=0.002"], ["this shell needs shell.N >= 69"], []),
    (["--set", "shell.geometry=table", "--set", "shell.table=nofile.csv"],
     ["shell.table", "file not found: 'nofile.csv'", "current directory"], ["torus", "knuckle", "shell.a ="]),
    (["--set", "shell.h", "inf"], ["bad --set argument 'shell.h'", "did you mean --set shell.h=inf?"], []),
    (["--set", "shell.h=", "0.01"], ["did you mean --set shell.h=0.01?"], []),
])
def test_the_refusal_gives_the_number_the_missing_file_and_the_form(args, needles, absent):
    """The mesh rule's refusal says what N this shell needs, a missing table says so (not the torus's rule),
    and a value split from its --set by a space is shown put back."""
    err = check_trace_rejects(args, *needles)
    for word in absent:
        assert word not in err, (word, err)


@pytest.mark.parametrize("command", ["trace", "classify"])
def test_a_very_fine_mesh_is_announced_with_an_estimate_before_it_runs(command, tmp_path):
    """Even with -q, a shell of 20000 nodes is not silent for a minute: a warning says roughly how long first.

    The expected duration is the measured one: the default path took 61.5 s (233 steps) at N = 20000 on one
    core of CI's machine (docs/scenes.md); a mesh of 3200 nodes (6 s) is not announced.
    """
    said: list[str] = []

    def run(scene: dict, progress: bool) -> Any:
        said.append(sys.stderr.getvalue())  # what was printed before the run started
        raise Reached(scene)

    model = dataclasses.replace(_REAL_LOAD("shell"), runner=run, classifier=run)
    for N, expected in ((20000, ["contin: warning: shell.N = 20000", "roughly 61 s", "0.27 s", "N = 3200"]),
                        (3200, [])):
        out = ["--out", str(tmp_path / "out")] if command == "trace" else []
        with pytest.raises(Reached):
            call(command, "-q", "--set", f"shell.N={N}", *out, load=lambda name: model)
        warned = " ".join(said.pop().split())
        assert all(needle in warned for needle in expected) and bool(warned) == bool(expected), warned


# ---- scene files --------------------------------------------------------------------------------------------
def _template(model: str) -> bytes:
    code, out, _ = call("models", model, "--toml")
    assert code == 0
    return out.encode()


TEMPLATES = {m: _template(m) for m in MODELS}


def _valid_scene(schema: Schema, scene: dict[str, dict[str, Any]]) -> bool:
    """Every field present, of its type, finite and in range (checked here, not by the loader)."""
    for section, keys in schema.sections.items():
        for key, fld in keys.items():
            value = scene[section][key]
            if isinstance(value, str) and value in fld.words:  # a word the field takes besides its type ("auto")
                continue
            if type(value) is not fld.type or (fld.type is float and not math.isfinite(value)):
                return False
            if not _fits(fld, value):
                return False
    return all(con.check(scene) for con in schema.constraints)


edit = st.one_of(
    st.tuples(st.just("truncate"), st.integers(0, 10**4)),
    st.tuples(st.just("flip"), st.integers(0, 10**4), st.integers(1, 255)),
    st.tuples(st.just("insert"), st.integers(0, 10**4), st.binary(min_size=1, max_size=6)),
    st.tuples(st.just("delete"), st.integers(0, 10**4), st.integers(1, 12)),
)


def corrupt(data: bytes, edits: list[tuple]) -> bytes:
    """Apply the edits in turn (positions taken modulo the current length)."""
    for op, pos, *arg in edits:
        at = pos % (len(data) + 1)
        if op == "truncate":
            data = data[:at]
        elif op == "flip" and data:
            at %= len(data)
            data = data[:at] + bytes([data[at] ^ arg[0]]) + data[at + 1:]
        elif op == "insert":
            data = data[:at] + arg[0] + data[at:]
        elif op == "delete":
            data = data[:at] + data[at + arg[0]:]
    return data


@PROPERTY
@given(st.sampled_from(MODELS), st.lists(edit, min_size=1, max_size=3))
def test_a_corrupted_scene_file_is_rejected_or_still_a_valid_scene(model, edits):
    """Truncations, byte flips, inserted bytes (invalid UTF-8, binary) and deletions in a model's full scene file:
    rejected with the file named, or still a valid scene (checked field by field here) and only then run."""
    data = corrupt(TEMPLATES[model], edits)
    with tempfile.TemporaryDirectory() as tmp:
        path, out = Path(tmp) / "scene.toml", Path(tmp) / "out"
        path.write_bytes(data)
        try:
            code, stdout, err = call("trace", "-q", "-m", model, str(path), "--out", str(out))
        except Reached as reached:  # the edits left a valid scene (a comment, a digit): only such a scene runs
            assert _valid_scene(schema_of(model), reached.scene)
            assert files_in(out) == []
            return
        assert_rejected(code, stdout, err)
        assert str(path) in err or "not allowed together" in err  # the file, or the fields of a broken rule
        assert files_in(out) == []


@pytest.mark.parametrize("content, needles", [
    (b"", ["is empty"]),
    (b"  \n\t\n", ["is empty"]),
    (bytes(range(256)), ["not UTF-8", "at byte 128"]),
    ("[shell]\nN = 30 # caf\xe9\n".encode("latin-1"), ["not UTF-8"]),
    ("[shell]\nN = 30\n".encode("utf-16"), ["not UTF-8", "at byte 0"]),
    (b"[shell]\nN = 30\n[continuation\nds = ", ["not valid TOML", "line 3"]),
    (b"[shell]\nN = 3\x000\n", ["not valid TOML"]),
    (b"[shell]\nN = 30\nN = 40\n", ["not valid TOML"]),
    (b"a = " + b"[" * 5000 + b"]" * 5000 + b"\n", ["nested too deeply"]),
    (b"N = 30\n", ["N = 30", "not inside a section", "[shell]"]),
    (b"shell = 1\n", ["'shell'", "must be a table [shell]", "R, E, nu, h, phi_hat, N, pole_ratio"]),
    (b"[[shell]]\nN = 30\n", ["must be a table [shell]"]),
    (b"[shell]\nN = {a = 1}\n", ["shell.N", "expected an integer, got a table"]),
    (b"[shell.sub]\na = 1\n", ["unknown scene key shell.sub"]),
    (b"[shell]\nh = 1979-05-27T07:32:00\n", ["shell.h = 1979-05-27T07:32:00", "expected a number, got a datetime"]),
])
def test_unusable_scene_files(content, needles):
    """Empty, binary, not UTF-8, invalid TOML, nested too deeply, or not a two-level scene."""
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "scene.toml"
        path.write_bytes(content)
        check_trace_rejects([str(path)], *needles)


def test_a_scene_that_is_a_directory_missing_or_unnamed(tmp_path):
    """A directory, a missing file and an empty name are refused as such (not read as '.')."""
    check_trace_rejects([str(tmp_path)], str(tmp_path), "Is a directory")
    check_trace_rejects([str(tmp_path / "none.toml")], "none.toml", "No such file")
    check_trace_rejects([""], "scene file name is empty")


def test_a_scene_file_with_a_byte_order_mark_is_read(tmp_path):
    """A UTF-8 byte-order mark, as some editors write, is not an error."""
    path = tmp_path / "scene.toml"
    path.write_bytes(b"\xef\xbb\xbf[shell]\nN = 30\n")
    with pytest.raises(Reached) as reached:
        call("trace", "-q", str(path), "--out", str(tmp_path / "out"))
    assert reached.value.scene["shell"]["N"] == 30


def test_an_output_name_taken_by_a_directory_is_refused_before_the_run(tmp_path):
    """An output that could not replace what is in DIR is found before the run, not after two others moved in."""
    out = tmp_path / "out"
    (out / "diagram.png").mkdir(parents=True)
    (out / "summary.json").write_text("old")
    code, stdout, err = call("trace", "-q", "-m", "bratu", "--out", str(out))  # Reached would mean it ran
    assert_rejected(code, stdout, err, str(out), "diagram.png is a directory")
    assert files_in(out) == ["diagram.png", "summary.json"] and (out / "summary.json").read_text() == "old"
    code, stdout, err = call("trace", "-q", "-m", "bratu", "--out", "")
    assert_rejected(code, stdout, err, "--out is empty")


# ---- --sweep ------------------------------------------------------------------------------------------------
num = st.floats(0.01, 1.4).map(lambda x: f"{x:.3g}")
BAD_SWEEPS = st.one_of(
    st.tuples(st.sampled_from(["shell.phi_hat", "shell.h", "shell.N"]), st.just("section.key=SPEC"),
              st.just("")),
    st.tuples(st.just("shell.phi_hat="), st.just("section.key=SPEC"), st.just("")),
    st.tuples(st.builds("shell.phi_hat={}:{}".format, num, num), st.just("three parts"), st.just("")),
    st.tuples(st.builds("shell.phi_hat={}:{}:{}:{}".format, num, num, num, num), st.just("three parts"), st.just("")),
    st.tuples(st.builds("shell.phi_hat=0.6:1.2:{}".format, st.integers(-5, 1)), st.just("must be an integer >= 2"),
              st.just("")),
    st.tuples(st.builds("shell.phi_hat=0.6:1.2:{}".format, st.floats(2.01, 9.99).map(repr)),
              st.just("must be an integer >= 2"), st.just("")),
    st.tuples(num.map(lambda x: f"shell.phi_hat={x}:{x}:3"), st.just("repeat one value"), st.just("")),
    st.tuples(st.builds("shell.h=log:{}:0.05:3".format, st.sampled_from(["0", "-0.01", "-1e-300"])),
              st.just("start > 0 and stop > 0"), st.just("")),
    st.tuples(st.builds("shell.h={}:0.05:3".format, words.map(lambda w: w.text)), st.just("is not a number"),
              st.just("")),
    st.tuples(num.map(lambda x: f"shell.phi_hat={x},1.3,{x}"), st.just("is given twice"), st.just("")),
    st.tuples(st.just("shell.phi_hat=0.6,,0.8"), st.just("empty value"), st.just("")),
    st.tuples(st.builds("shell.N=40:{}:3".format, st.sampled_from([41, 43, 101])), st.just("takes integers"),
              st.just("")),
    st.tuples(st.just("output.figure=0:1:2"), st.just("only a numeric key takes a range"), st.just("")),
    st.tuples(st.builds("shell.phi_hat=-{}:{}:3".format, st.sampled_from(["1e308", "1.7e308"]),
                        st.sampled_from(["1e308", "1.7976931348623157e308"])), st.just("too far apart"),
              st.just("")),
    st.tuples(st.builds("shell.h=0.01:1{}:3".format, st.just("0" * 400)), st.just("beyond the range"), st.just("")),
    st.tuples(st.builds("shell.phi_hat=1.0,{}".format, st.sampled_from(["nan", "inf", "1e999", "1" + "0" * 400])),
              st.just("expected a finite number"), st.just("a float in (0, 1.5708)")),
    st.tuples(st.builds("shell.N={},30".format, st.integers(max_value=9) | st.integers(min_value=20001)),
              st.just("is out of range"), st.just("an integer >= 10 and <= 20000")),
    st.tuples(st.builds("shell.{}=1,2".format, names.filter(lambda n: n not in schema_of("shell").sections["shell"])),
              st.just("unknown scene key shell."), st.just("")),
)


@PROPERTY
@given(BAD_SWEEPS)
def test_a_bad_sweep_names_the_key_and_what_is_allowed(case):
    """Malformed specs, bad counts, repeats, overflowing ranges, bad values: the key and the rule, no CSV."""
    spec, needle, allowed = case
    key = spec.partition("=")[0].strip()
    with tempfile.TemporaryDirectory() as tmp:
        csv_path = Path(tmp) / "sweep.csv"
        code, out, err = call("classify", "-q", "--set", "output.figure=false", f"--sweep={spec}", "--csv",
                              str(csv_path))
        assert_rejected(code, out, err, needle, key, allowed)
        assert files_in(Path(tmp)) == []  # nothing ran, no CSV was started


# ---- the saved sweep CSV ------------------------------------------------------------------------------------
def _toy_classify(scene: dict, progress: bool) -> Classification:
    toy = scene["toy"]
    if toy["n"] == 3 and toy["kind"] == "y":
        return Classification(None, failure="no class for n = 3, kind = y")
    product = toy["a"] * toy["n"]
    return Classification("big" if product > 2 else "small",
                          values={"product": product, "even": toy["n"] % 2 == 0, "absent": None, "note": "text"})


TOY = SceneModel("toy", "a stand-in that classifies at once",
                 Schema({"toy": {"n": Field(int, 1, lambda n: n >= 1, "an integer >= 1"),
                                 "kind": Field(str, "x", lambda k: k in ("x", "y"), 'one of "x", "y"'),
                                 "a": Field(float, 1.0, lambda a: 0 < a <= 10, "a float in (0, 10]")}}),
                 lambda scene, progress: TraceResult(branches=[]), classifier=_toy_classify)
SWEEP = ["classify", "-q", "--workers", "1", "--sweep", "toy.n=1,2,3", "--sweep", "toy.kind=x,y"]
COMBOS = {(n, kind) for n in (1, 2, 3) for kind in ("x", "y")}


def toy_sweep(csv_path: Path, *more: str) -> tuple[int, str, str]:
    return call(*SWEEP, *more, "--csv", str(csv_path), load=lambda name: TOY)


def _complete_csv() -> bytes:
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "toy.csv"
        code, _, err = toy_sweep(path)
        assert code == 1, err  # the combination n = 3, kind = y has no class
        return path.read_bytes()


COMPLETE = _complete_csv()
HEADER = COMPLETE.decode().splitlines()[0]


def assert_complete_and_sound(path: Path, code: int) -> None:
    """The CSV after an accepted run: one row per combination, each consistent with its scene, cells as written."""
    columns, rows = read_sweep_csv(path)
    assert columns[:4] == ["toy.n", "toy.kind", "label", "status"] and columns[-3:] == ["wall_time_s", "failure",
                                                                                        "scene"]
    ours = [r for r in rows if (r["toy.n"], r["toy.kind"]) in COMBOS]
    assert sorted((r["toy.n"], r["toy.kind"]) for r in ours) == sorted(COMBOS)  # each exactly once
    for r in rows:
        assert r["scene"]["toy"]["n"] == r["toy.n"] and r["scene"]["toy"]["kind"] == r["toy.kind"]
        assert r["label"] is not None or r["failure"]
    with open(path, newline="", encoding="utf-8") as fh:  # independently of read_sweep_csv: finite numbers only
        for rec in csv.DictReader(fh):
            assert (rec["status"] == "ok") == (rec["failure"] == ""), (rec["status"], rec["failure"])
            for col in columns[columns.index("status") + 1:-2]:
                cell = rec[col]
                assert cell in ("", "true", "false") or math.isfinite(float(cell)), (col, cell)
    assert code == (1 if any(r["failure"] for r in ours) else 0)


CELL_TEXTS = st.sampled_from(["nan", "inf", "-1", "", "garbage", "{}", "1e999", "true", "0", "\x00", "é"]) | texts
LINE_EDITS = {
    "truncate": st.tuples(st.just("truncate"), st.integers(0, 10**4)),
    "flip": st.tuples(st.just("flip"), st.integers(0, 10**4), st.integers(1, 255)),
    "insert": st.tuples(st.just("insert"), st.integers(0, 10**4), st.binary(min_size=1, max_size=6)),
    "delete": st.tuples(st.just("delete"), st.integers(0, 10**4), st.integers(1, 12)),
    "dup_line": st.tuples(st.just("dup_line"), st.integers(0, 50)),
    "drop_line": st.tuples(st.just("drop_line"), st.integers(1, 50)),
    "swap_lines": st.tuples(st.just("swap_lines"), st.integers(0, 50), st.integers(0, 50)),
    "cell": st.tuples(st.just("cell"), st.integers(0, 500), CELL_TEXTS),
}
# each kind of edit as likely as the others, a cell of a data row twice as likely
line_edit = st.sampled_from([*LINE_EDITS, "cell"]).flatmap(LINE_EDITS.__getitem__)


def corrupt_csv(data: bytes, edits: list[tuple]) -> bytes:
    """Byte edits (see :func:`corrupt`) and line edits: duplicate, drop or swap lines, replace a cell."""
    for op, pos, *arg in edits:
        if op in ("truncate", "flip", "insert", "delete"):
            data = corrupt(data, [(op, pos, *arg)])
            continue
        lines = data.split(b"\n")
        i = pos % len(lines)
        if op == "dup_line":
            lines.insert(i, lines[i])
        elif op == "drop_line":
            del lines[i]
        elif op == "swap_lines":
            j = arg[0] % len(lines)
            lines[i], lines[j] = lines[j], lines[i]
        elif op == "cell":
            try:
                recs = list(csv.reader(io.StringIO(data.decode("utf-8"))))
            except (UnicodeDecodeError, csv.Error):
                continue
            cells = [(r, c) for r in range(1, len(recs)) for c in range(len(recs[r]))]  # the data rows
            if cells:
                r, c = cells[pos % len(cells)]
                recs[r][c] = arg[0]
                buf = io.StringIO()
                csv.writer(buf, lineterminator="\n").writerows(recs)
                data = buf.getvalue().encode("utf-8")
            continue
        data = b"\n".join(lines)
    return data


@PROPERTY
@given(st.lists(line_edit, min_size=1, max_size=3))
def test_a_corrupted_sweep_csv_is_refused_unchanged_or_resumed_soundly(edits):
    """Byte and line edits of a finished sweep's CSV: refused with the file byte for byte as it was, or resumed
    into a CSV with every combination once, each row consistent with its scene and only finite numbers."""
    data = corrupt_csv(COMPLETE, edits)
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "toy.csv"
        path.write_bytes(data)
        code, out, err = toy_sweep(path)
        if code == 2:
            assert_rejected(code, out, err, str(path))
            assert path.read_bytes() == data  # byte for byte
            assert files_in(Path(tmp)) == ["toy.csv"]  # no temporary left either
        else:
            assert "Traceback" not in err and "internal error" not in err
            assert_complete_and_sound(path, code)


@PROPERTY
@given(st.binary(min_size=1, max_size=200) | texts.filter(bool).map(lambda t: t.encode("utf-8")))
def test_a_file_that_is_not_a_sweep_csv_is_never_overwritten(data):
    """Any other file given as --csv is refused and kept (only --no-resume overwrites it)."""
    cut_header = b"\n" not in data and HEADER.startswith(data.decode("utf-8", "replace"))
    assume(not cut_header)  # a sweep's header cut short by an interrupt is indistinguishable: it is restarted
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "results.csv"
        path.write_bytes(data)
        code, out, err = toy_sweep(path)
        assert_rejected(code, out, err, str(path))
        assert path.read_bytes() == data


def _with_cell(column: str, text: str, line: int = 2) -> bytes:
    recs = list(csv.reader(io.StringIO(COMPLETE.decode())))
    recs[line - 1][recs[0].index(column)] = text
    buf = io.StringIO()
    csv.writer(buf, lineterminator="\n").writerows(recs)
    return buf.getvalue().encode()


def _named(value: object) -> str:
    """Test ids from a case's name: its data hold the toy sweep's wall times, which differ between
    processes, and pytest-xdist requires every worker to collect the same ids."""
    return value if isinstance(value, str) else type(value).__name__


DAMAGED_CELLS = [(col, text) for col in ("product", "even", "absent", "wall_time_s")
                 for text in ("nan", "NaN", "inf", "-inf", "1e999", "garbage", "[]", "null")]
DAMAGED_CELLS += [("wall_time_s", "-1"), ("wall_time_s", "true"), ("toy.n", "7"), ("toy.n", "nan"), ("toy.n", ""),
                  ("toy.kind", "z"), ("scene", ""), ("scene", "{"), ("scene", "[]"), ("scene", "NaN"),
                  ("scene", '{"toy": {"n": NaN, "kind": "x", "a": 1.0}}'), ("scene", '{"toy": 1}')]


@pytest.mark.parametrize("column, text", DAMAGED_CELLS)
def test_a_damaged_cell_names_the_line_and_the_column(tmp_path, column, text):
    """A cell the sweep never writes (NaN, inf, text for a number, a swept value its scene does not have)."""
    data = _with_cell(column, text, line=3)
    path = tmp_path / "toy.csv"
    path.write_bytes(data)
    code, out, err = toy_sweep(path)
    assert_rejected(code, out, err, f"line 3 of the sweep CSV {str(path)!r} is damaged", f"its {column} cell",
                    "--no-resume")
    assert path.read_bytes() == data
    if column not in ("toy.n", "toy.kind"):  # read_sweep_csv, which knows no sweep, reads cells the same way
        with pytest.raises(SweepError, match=f"line 3 .* its {column} cell"):
            read_sweep_csv(path)


@pytest.mark.parametrize("name, data, needles", [
    ("wrong header", b"w,F\n0.1,2.0\n", ["not a sweep CSV", "w, F"]),
    ("another sweep", COMPLETE.replace(b"toy.kind", b"toy.a"), ["holds a sweep over toy.n, toy.a"]),
    ("another scene", COMPLETE.replace(b'""a"":1.0', b'""a"":2.0'), ["another scene", "toy.a = 2.0 there"]),
    ("binary", bytes(range(256)) * 4, ["not a sweep CSV", "not UTF-8"]),
    ("latin-1", COMPLETE.replace(b"small", "sm\xe4ll".encode("latin-1")), ["not UTF-8"]),
    ("a line cut in the middle", COMPLETE.replace(b"\n", b"\n" + HEADER.encode()[:30] + b"\n", 1),
     ["line 2", "fields"]),
    ("a blank line", COMPLETE.replace(b"\n", b"\n\n", 1), ["line 2", "0 fields"]),
    ("one line, no newline", b"precious data", ["not a sweep CSV", "precious data"]),
    ("a field over the csv limit", HEADER.encode() + b"\n\"" + b"x" * 200_000 + b"\"\n", ["not a sweep CSV"]),
    ("no class and no failure", _with_cell("label", ""), ["line 2", "neither a class (label) nor a failure"]),
], ids=_named)
def test_a_csv_that_cannot_be_resumed_is_left_as_it_was(tmp_path, name, data, needles):
    """Wrong header, another sweep or scene, binary, cut or blank lines, a one-line file, an oversized field."""
    path = tmp_path / "toy.csv"
    path.write_bytes(data)
    code, out, err = toy_sweep(path)
    assert_rejected(code, out, err, str(path), *needles)
    assert path.read_bytes() == data and files_in(tmp_path) == ["toy.csv"]


def test_a_csv_path_that_is_a_directory(tmp_path):
    """--csv naming a directory is refused and nothing is written into it."""
    code, out, err = toy_sweep(tmp_path)
    assert_rejected(code, out, err, str(tmp_path), "is a directory")
    assert files_in(tmp_path) == []


@pytest.mark.parametrize("name, data", [
    ("empty: created, then interrupted before the first row", b""),
    ("the header cut short", COMPLETE[:17]),
    ("the header only", COMPLETE[:len(HEADER) + 1]),
    ("the last row cut short", COMPLETE[:-30]),
    ("rows missing", b"\n".join(COMPLETE.split(b"\n")[:3]) + b"\n"),
    ("a duplicated row (the last one counts)", COMPLETE + COMPLETE.split(b"\n")[2] + b"\n"),
], ids=_named)
def test_what_an_interrupted_sweep_leaves_is_resumed(tmp_path, name, data):
    """The states an interrupt can leave (by design not errors) are completed into a sound CSV."""
    path = tmp_path / "toy.csv"
    path.write_bytes(data)
    code, _, err = toy_sweep(path)
    assert "Traceback" not in err
    assert_complete_and_sound(path, code)
    assert files_in(tmp_path) == ["toy.csv"]


def test_a_rejected_scene_leaves_the_sweep_csv_alone(tmp_path):
    """A bad scene or sweep is refused before the CSV is opened: an existing one is unchanged, none is created."""
    path = tmp_path / "toy.csv"
    path.write_bytes(COMPLETE)
    for bad in (["--set", "toy.a=nan"], ["--set", "toy.a=11"], ["--set", "toy.b=1"], ["--sweep", "toy.a=1,1"]):
        code, out, err = toy_sweep(path, *bad)
        assert_rejected(code, out, err, "toy.")
        assert path.read_bytes() == COMPLETE
    code, out, err = toy_sweep(tmp_path / "new.csv", "--set", "toy.a=-1")
    assert_rejected(code, out, err, "toy.a = -1", "a float in (0, 10]")
    assert files_in(tmp_path) == ["toy.csv"]


# ---- the process ------------------------------------------------------------------------------------------
def test_bad_input_exits_2_without_a_traceback_as_a_process(tmp_path):
    """A handful of rejections through ``python -m contin.app.cli``, run side by side."""
    binary = tmp_path / "binary.toml"
    binary.write_bytes(bytes(range(256)))
    garbage = tmp_path / "garbage.csv"
    garbage.write_bytes(b"toy,label\n\xff\xfe garbage\n")
    out = tmp_path / "out"
    out.mkdir()
    cases = {
        "nan": (["trace", "--set", "shell.h=nan", "--out", str(out)], "shell.h"),
        "huge N": (["trace", "--set", "shell.N=99999999999999999999999", "--out", str(out)], "shell.N"),
        "binary scene": (["trace", str(binary), "--out", str(out)], "not UTF-8"),
        "directory scene": (["trace", str(tmp_path), "--out", str(out)], "Is a directory"),
        "bad --set": (["trace", "--set", "shell.h", "--out", str(out)], "section.key=value"),
        "overflowing range": (["classify", "--sweep", "shell.h=-1e308:1.7e308:3", "--csv", str(tmp_path / "x.csv")],
                              "too far apart"),
        "garbage CSV": (["classify", "-q", "-j", "1", "--set", "shell.N=30", "--sweep", "shell.phi_hat=1.0,1.2",
                         "--csv", str(garbage)], "not UTF-8"),
    }
    env = {k: v for k, v in os.environ.items() if k != "CONTIN_TRACEBACK"}
    env["MPLBACKEND"] = "Agg"
    procs = {name: subprocess.Popen([sys.executable, "-m", "contin.app.cli", *argv], stdout=subprocess.PIPE,
                                    stderr=subprocess.PIPE, text=True, env=env, cwd=tmp_path)
             for name, (argv, _) in cases.items()}
    for name, proc in procs.items():
        stdout, stderr = proc.communicate(timeout=120)
        assert proc.returncode == 2, (name, stderr)
        assert_rejected(2, stdout, stderr, cases[name][1])
    assert files_in(out) == [] and garbage.read_bytes() == b"toy,label\n\xff\xfe garbage\n"
    assert not (tmp_path / "x.csv").exists()


# ---- Ctrl-C while the command starts ----------------------------------------------------------------------
ROOT = Path(__file__).resolve().parents[1]
#: What the console script runs (``contin = "contin.launch:main"`` in pyproject.toml).
LAUNCH = "import sys; from contin.launch import main; sys.exit(main())"


def _launcher() -> Any:
    """``contin.launch``, the console script's module."""
    return importlib.import_module("contin.launch")


class _InterruptedImport:
    """A meta-path finder that raises KeyboardInterrupt on importing ``contin.app.cli``, as a Ctrl-C there would."""

    def find_spec(self, name: str, path: Any = None, target: Any = None) -> None:
        if name == "contin.app.cli":
            raise KeyboardInterrupt
        return None


def test_ctrl_c_while_the_modules_load_is_an_interrupt_not_a_traceback(capsys):
    """An interrupt while ``contin.app.cli`` is imported: 'contin: interrupted' and status 130."""
    launcher = _launcher()
    finder = _InterruptedImport()
    with mock.patch.dict(sys.modules):
        sys.modules.pop("contin.app.cli", None)
        sys.meta_path.insert(0, finder)
        try:
            code = launcher.main(["models"])
        finally:
            sys.meta_path.remove(finder)
    assert code == 130 and capsys.readouterr().err == "contin: interrupted\n"
    assert launcher.main(["models", "bratu"]) == 0 and "bratu" in capsys.readouterr().out  # otherwise: contin


def test_ctrl_c_at_start_up_as_a_process():
    """SIGINT while the command line's modules load: no traceback; 130 and the interrupt message."""
    # The signal must land inside the import of contin.app.cli.  A fixed delay after start-up misses it on a
    # busy machine (the import ends first and the command exits 0), so the child announces the moment
    # its import of contin.app.scene (which contin.app.cli imports; numpy no longer loads for 'contin models')
    # begins and waits there, inside the real import statement, for the signal.
    stall = ("import sys, time\n"
             "class Stall:\n"
             "    def find_spec(self, name, path=None, target=None):\n"
             "        if name == 'contin.app.scene':\n"
             "            sys.meta_path.remove(self)\n"
             "            print('importing contin.app.scene', flush=True)\n"
             "            time.sleep(60)\n"
             "        return None\n"
             "sys.meta_path.insert(0, Stall())\n")
    proc = subprocess.Popen([sys.executable, "-c", stall + LAUNCH, "models"], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, cwd=ROOT)
    assert proc.stdout.readline() == "importing contin.app.scene\n"  # inside main(), in the import of contin.app.cli
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=60)
    assert "Traceback" not in err
    assert proc.returncode == 130 and err == "contin: interrupted\n"
