"""The declared layouts, the registry of torque terms and the declared kinds: what is generated
from the declarations (offsets, packing, codes, the program's walk) and what they refuse."""

from __future__ import annotations

import re
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from tumble import kernels
from tumble.app.heyoka_peer import _Frame
from tumble.errors import ParameterError
from tumble.kernels import terms
from tumble.kernels.kinds import KINDS
from tumble.kernels.layout import Field, Layout
from tumble.kernels.terms import KeySpec
from tumble.kernels.torque import moments
from tumble.torques import ConstantBodyTorque, GravityGradientTorque, LinearDrag

SRC = Path(kernels.__file__).parent


def test_offsets_follow_the_declared_order_and_sizes():
    layout = Layout("demo", (Field("a"), Field("v", 3), Field("m", 9), Field("b")), tail="rest")
    assert tuple(layout.at) == (0, 1, 4, 13)
    assert layout.size == 14
    packed = layout.pack({"a": 1.0, "v": [2, 3, 4], "m": np.eye(3), "b": 5.0}, tail=[6.0, 7.0])
    assert len(packed) == 16
    back = layout.unpack(packed)
    assert back["a"] == 1.0 and back["b"] == 5.0
    np.testing.assert_array_equal(back["v"], [2, 3, 4])
    np.testing.assert_array_equal(back["m"], np.eye(3))
    np.testing.assert_array_equal(back["rest"], [6.0, 7.0])


@pytest.mark.parametrize(
    ("values", "message"),
    [
        ({"x": 1.0}, r"demo\.y is missing"),
        ({"x": 1.0, "y": [1, 2, 3], "z": 0.0}, r"unknown field"),
        ({"x": 1.0, "y": [1, 2]}, r"demo\.y must have 3 component"),
        ({"x": np.nan, "y": [1, 2, 3]}, r"demo\.x must be finite"),
        ({"x": -1.0, "y": [1, 2, 3]}, r"demo\.x = \[-1\.0\] is outside \[0, 2\] \[s\]"),
    ],
)
def test_packing_names_the_field_it_refuses(values, message):
    layout = Layout("demo", (Field("x", 1, "s", low=0.0, high=2.0), Field("y", 3)))
    with pytest.raises(ParameterError, match=message):
        layout.pack(values)


def test_a_layout_without_a_tail_refuses_one():
    with pytest.raises(ParameterError, match="no variable-length tail"):
        Layout("demo", (Field("x"),)).pack({"x": 1.0}, tail=[1.0])


def test_codes_are_the_registration_order_and_names_are_unique():
    assert [terms.code(t.name) for t in terms.TERMS] == list(range(1, len(terms.TERMS) + 1))
    assert len({t.name for t in terms.TERMS}) == len(terms.TERMS)
    with pytest.raises(ParameterError, match="no torque term 'nothing'"):
        terms.code("nothing")
    with pytest.raises(ParameterError, match="unknown term code 99"):
        terms.term_of(99)


def test_every_term_declares_a_compiled_moment_and_what_it_reads():
    for term in terms.TERMS:
        assert term.moment is not None, term.name
        assert term.reads <= {"rate", "attitude", "time", "orbit", "field"}, term.name
        # a term evaluated along an orbit reads the time, since the orbit moves
        assert not term.along_orbit or "time" in term.reads, term.name


def test_a_program_walks_by_each_terms_own_size():
    # The user term's payload has a tail of its own length; the walk must not read a parameter
    # as the next term's code (the header carries each payload's size).
    user = terms.compiled_term("user", {"address": 0.0, "record": 0.0, "n": 2.0}, tail=[8.0, 9.0])
    body = terms.compiled_term("body_constant", {"moment": [1.0, 2.0, 3.0]}, factor=0.5)
    program = terms.flatten([user, body])
    walked = terms.walk(program)
    assert [t.name for t, _, _ in walked] == ["user", "body_constant"]
    assert walked[1][1] == 0.5
    np.testing.assert_array_equal(walked[0][2], [0.0, 0.0, 2.0, 8.0, 9.0])
    i = 1
    for _ in range(2):
        i = int(terms.next_term.py_func(program, i))
    assert i == program.size


def test_torques_pack_by_the_declared_layout():
    gg = GravityGradientTorque([1.0, 2.0, 3.0], 0.5, [0.0, 0.0, 1.0], 0.25)
    (which, factor, payload) = gg.compiled_terms()[0]
    values = terms.term_of(which).values(payload)
    assert terms.term_of(which).name == "gravity_gradient" and factor == 1.0
    np.testing.assert_array_equal(values["inertia"], [1.0, 2.0, 3.0])
    assert values["n"] == 0.5 and values["u0"] == 0.25
    np.testing.assert_array_equal(values["basis"], gg.basis)
    torque = 2.0 * (ConstantBodyTorque([1.0, 0.0, 0.0]) + LinearDrag(np.eye(3)))
    assert torque.rate_only and not torque.along_orbit
    assert not gg.rate_only


def test_a_kernel_is_checked_against_its_kinds_declaration():
    with pytest.raises(
        ParameterError, match="rotating field: 3 parameters, the layout declares 13"
    ):
        kernels.Kernel(kernels.KIND_ROTATING_FIELD, np.ones(3))
    with pytest.raises(ParameterError, match="cannot watch"):
        kernels.Kernel(
            kernels.KIND_FIELD_AVERAGED, np.ones(6), event=kernels.EVENT_TRIAXIAL_SEPARATRIX
        )
    with pytest.raises(ParameterError, match="no right-hand side of kind 77"):
        kernels.Kernel(77, np.ones(3))
    # every kind the right-hand side dispatches on is declared
    assert set(KINDS) == {getattr(kernels, n) for n in kernels.__all__ if n.startswith("KIND_")}


def test_a_kernel_evaluated_from_python_compiles_its_kind_alone():
    # Each kind gets its own entry (the kind a constant of the closure, so that its dispatch
    # folds to that kernel: an entry taking the kind at run time compiled every kind, a
    # minute and a half from a cold cache); an unknown kind is NaN without compiling anything.
    from tumble.kernels import rhs

    y = np.array([0.3, 0.2, 1.0, 0.7])
    p = np.array([0.01, 0.2, 0.8, 1.0, 1.6, 2.2])
    got = rhs.evaluate(kernels.KIND_FIELD_AVERAGED, 0.0, y, p)
    assert got.shape == (4,) and np.all(np.isfinite(got))
    entry = rhs._EVALUATORS[("rhs", kernels.KIND_FIELD_AVERAGED)]
    assert len(entry.signatures) == 1
    assert np.all(np.isnan(rhs.evaluate(77, 0.0, y, p)))
    assert np.all(np.isnan(rhs.evaluate_repeatedly(77, 0.0, y, p, 3, 0.0)))
    assert ("rhs", 77) not in rhs._EVALUATORS and ("repeat", 77) not in rhs._EVALUATORS


def test_kernels_read_no_slot_by_a_literal_position():
    # Compiled code reads its parameters by the declared names (Layout.at); a literal offset
    # such as ``p[4]`` or ``prog[v + 3]`` is allowed only in the generic readers of layout.py.
    pattern = re.compile(r"\b(p|prog|params|program|payload)\[(\w+ ?[+-] ?)?[0-9]+\]")
    found = []
    for path in sorted(SRC.rglob("*.py")):
        if path.name == "layout.py":
            continue
        for number, line in enumerate(path.read_text().splitlines(), 1):
            if pattern.search(line):
                found.append(f"{path.relative_to(SRC)}:{number}: {line.strip()}")
    assert not found, "\n".join(found)


# heyoka's functions on floats: a term's transcription for the heyoka peer evaluated
# numerically, to hold it to the compiled moment without heyoka installed.
NUMBERS = SimpleNamespace(sin=np.sin, cos=np.cos, sqrt=np.sqrt, exp=np.exp)


def _values(layout: Layout, rng: np.random.Generator) -> dict[str, np.ndarray]:
    """Random values of every field of a layout, inside each field's declared range."""
    out = {}
    for f in layout.fields:
        x = rng.normal(size=f.size)
        lo, hi = max(f.low, -2.0), min(f.high, 2.0)
        out[f.name] = (lo + (hi - lo) * (np.tanh(x) + 1.0) / 2.0).reshape(
            (3, 3) if f.size == 9 else (3,) if f.size == 3 else ()
        )
    return out


@pytest.mark.parametrize(
    "term", [t for t in terms.TERMS if t.peer is not None], ids=lambda t: t.name
)
def test_every_peer_transcription_is_the_compiled_moment(term):
    rng = np.random.default_rng(11)
    for _ in range(5):
        values = _values(term.layout, rng)
        code, factor, payload = terms.compiled_term(term.name, values, factor=0.7)
        t, q, w = rng.uniform(0.0, 5.0), rng.normal(size=4), rng.normal(size=3)
        frame = _Frame(NUMBERS, list(q))
        got = term.peer(term.values(payload), factor, t, list(w), frame, NUMBERS)
        if got is None:  # no Taylor form (the quadratic drag)
            continue
        program = terms.flatten([(code, factor, payload)])
        want = moments(program, np.array([t]), q[None, :], w[None, :])[0]
        # Two transcriptions of the same formula in double precision: round-off apart.
        np.testing.assert_allclose(np.asarray(got, dtype=float), want, rtol=1e-12, atol=1e-12)


def test_the_keys_read_from_source_are_the_declared_ones():
    # The orbiting body's schema reads the term modules' ORBIT_KEYS from their source, so that
    # a scenario validates before numba loads; they must be the imported declarations.
    specs = terms.orbit_key_specs()
    declared = terms.ORBIT_KEYS
    assert [s.name for s in specs] == [k.name for k in declared]
    for read, key in zip(specs, declared, strict=True):
        assert read == KeySpec(key.name, key.kind, key.meaning, key.unit, key.default, key.doc)
