"""Sunlight on the orbiting body's scenario: the ``[surface]`` shapes against their Python
builders, averaged against full for a tumbling box-wing satellite in GEO, and bad input refused
in one line."""

from __future__ import annotations

import tomllib

import numpy as np
import pytest
from files import EXAMPLES, one_line_error

from tumble.errors import ParameterError
from tumble.integrate import simulate
from tumble.io import parse_scenario
from tumble.kernels.terms import code, term_of
from tumble.kernels.terms.solar_radiation import FACET, principal
from tumble.space import facets as F

BOX_WING = EXAMPLES / "ob_geo_box_wing.toml"
TUMBLING = EXAMPLES / "ob_geo_box_wing_tumbling.toml"


def _table(tmp_path, surface: dict) -> np.ndarray:
    """The facet table the scenario makes of ``surface``: the sunlight term's payload, turned
    back from the principal axes into the scenario's body axes."""
    data = tomllib.loads(BOX_WING.read_text(encoding="utf-8"))
    data["surface"] = surface
    params = parse_scenario(data, str(tmp_path / "s.toml")).request.params
    (payload,) = [payload for code, _, payload in params.torque.compiled_terms()
                  if term_of(code).name == "solar_radiation"]  # fmt: skip
    values = term_of(code("solar_radiation")).values(payload)
    return principal(values["facets"].reshape(-1, FACET.size), params.axes.T)


def test_the_example_box_wing_is_the_python_builders(tmp_path):
    data = tomllib.loads(BOX_WING.read_text(encoding="utf-8"))
    s = data["surface"]
    got = _table(tmp_path, s)
    bus = F.Optics(s["specular"], s["diffuse"], s["emissivity"], 0.0)
    cells = F.Optics(s["array_specular"], s["array_diffuse"], s["array_emissivity"],
                     s["array_back_emissivity"])  # fmt: skip
    normal = np.array(s["array_normal"]) / np.linalg.norm(s["array_normal"])
    want = F.box_wing(s["size"], bus, s["array_area"], normal, s["array_centre"], cells)
    want = want.shifted(-np.array(s["centre_of_mass"]))
    # The same arithmetic: equal to the last bit.
    np.testing.assert_array_equal(got, want.table())


def test_facets_listed_one_by_one(tmp_path):
    surface = {
        "shape": "facets",
        "facet": [
            {"area": 2.0, "normal": [0.0, 0.0, 2.0], "centre": [0.0, 0.0, 1.0], "specular": 0.2},
            {
                "area": 1.0,
                "normal": [1.0, 0.0, 0.0],
                "centre": [0.5, 0.0, 0.0],
                "diffuse": 0.4,
                "emissivity": 0.9,
                "back_emissivity": 0.9,
            },
        ],
        "centre_of_mass": [0.0, 0.0, 0.1],
    }
    got = _table(tmp_path, surface)
    want = F.Facets.of([2.0], [0.0, 0.0, 1.0], [0.0, 0.0, 0.9], F.Optics(0.2, 0.0)) + F.Facets.of(
        [1.0], [1.0, 0.0, 0.0], [0.5, 0.0, -0.1], F.Optics(0.0, 0.4, 0.9, 0.9)
    )
    np.testing.assert_allclose(got, want.table(), rtol=0.0, atol=1e-15)


def test_a_mesh_file_beside_the_scenario(tmp_path):
    trimesh = pytest.importorskip("trimesh")
    trimesh.creation.box(extents=[1.0, 2.0, 3.0]).export(tmp_path / "bus.stl")
    got = _table(tmp_path, {"shape": "mesh", "mesh": "bus.stl", "diffuse": 0.3})
    want = F.from_mesh(tmp_path / "bus.stl", F.Optics(0.0, 0.3))
    np.testing.assert_array_equal(got, want.table())
    assert got.shape[0] == 12  # two triangles a face
    np.testing.assert_allclose(want.area.sum(), 2.0 * (2.0 + 3.0 + 6.0), rtol=1e-12)


def test_averaged_against_full_for_a_tumbling_box_wing_in_geo():
    # Ten days of the tumbling example (its period and the direction of L): the averaged
    # equations average the exact illumination over the precession and take 8 intervals of the
    # polhode (an error of at most a few 1e-3 of the moment), the orbit with its eclipse
    # fraction (the full run has the conical shadow). The period falls by 1.2 %; the averaged
    # run's period is off by 6.5e-5 at most (0.5 % of the change), L by 0.0066° (measured).
    data = tomllib.loads(TUMBLING.read_text(encoding="utf-8"))
    data["run"] = {"t_end_days": 10.0, "samples": 11, "methods": ["full", "averaged"]}
    request = parse_scenario(data, str(TUMBLING)).request
    runs = {m: simulate(request.model, request.params, request.initial, request.tau, m).columns
            for m in ("full", "averaged")}  # fmt: skip
    f, a = runs["full"], runs["averaged"]
    assert 0.0 < f["k2"][0] < 1.0  # a tumble
    assert abs(f["period"][-1] / f["period"][0] - 1.0) > 0.01  # the period moves
    assert np.max(np.abs(a["period"] / f["period"] - 1.0)) <= 2e-4
    Lf = np.stack([f[f"L{i}"] for i in (1, 2, 3)], axis=1)
    La = np.stack([a[f"L{i}"] for i in (1, 2, 3)], axis=1)
    cos = np.sum(Lf * La, axis=1) / np.linalg.norm(Lf, axis=1) / np.linalg.norm(La, axis=1)
    assert np.degrees(np.max(np.arccos(np.clip(cos, -1.0, 1.0)))) <= 0.02


BAD = [
    ('solar_radiation = "conical"', 'solar_radiation = "penumbral"', "torques.solar_radiation"),
    ("size = [2.0, 2.0, 2.3]", "size = [2.0, 0.0, 2.3]", "surface.size"),
    ('shape = "box_wing"', 'shape = "sphere"', "surface.shape"),
    ("array_area = 12.0", "array_area = -1.0", "surface.array_area"),
    ("array_specular = 0.05", "array_specular = 0.99", "specular + diffuse"),
    ('shape = "box_wing"', 'shape = "mesh"\nmesh = "missing.stl"', "surface.mesh"),
    ('shape = "box_wing"', 'shape = "facets"', "surface.facet"),
]


@pytest.mark.parametrize(("old", "new", "needle"), BAD)
def test_bad_input_gets_one_clear_line(tmp_path, old, new, needle):
    assert needle in one_line_error(tmp_path, BOX_WING, old, new)


def test_sunlight_needs_a_surface():
    data = tomllib.loads(BOX_WING.read_text(encoding="utf-8"))
    del data["surface"]
    with pytest.raises(ParameterError, match=r"needs the body's surface: give \[surface\]"):
        parse_scenario(data, str(BOX_WING))
