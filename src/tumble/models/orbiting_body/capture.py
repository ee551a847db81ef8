"""Where an orbiting body's averaged run hands over to the full equations: the gravity
gradient's capture.

The averaged equations of an orbiting body average over the body's own rotation and over the
orbit, which holds while the body turns fast against the orbit. An object slowed by eddy
currents towards the orbital rate n meets the gravity gradient's well about the local
vertical: the body's rate relative to the orbiting frame, of order rate − n, becomes
comparable with the libration frequency in that well, ω_lib = n √(3 (I3 − I1)/I2) (the
pitch libration of a body whose extreme moments are I1 < I3, Kane & Likins; Hughes,
*Spacecraft Attitude Dynamics*, §9.3), and the body may be captured into libration, a motion
the averaged state [L_ξ, 2T/L²] cannot describe. A hybrid run (``run.averaged_method =
"hybrid"``) therefore hands over to the full equations once

    rate < n + CAPTURE_MARGIN · ω_lib,

and hands back when the rate rises above the edge by half its distance from n again
(:attr:`tumble.models.base.Crossing.LEAVE`). A sphere (ω_lib = 0) is never captured: its edge
is n itself, below any rate its eddy currents leave it with.

The state handed over is a point of the Euler–Poinsot motion with the averaged state's L_ξ
and T: the body rate where the polhode crosses the plane of the largest and the smallest
moments (:func:`tumble.unperturbed.euler_poinsot.polhode_point`), and the attitude the
smallest rotation taking the body direction of L to L_ξ, turned into the averaged run's sense
of rotation about the axis its polhode encircles (:func:`tumble.averaging.sense_turn`). The
averaged state has no phases (first order), so they are chosen, not known: an outcome that
depends on them (a capture decided within one libration) is one draw of that dependence.

The averaged equations hold that sense (a torque fixed in the body, sunlight on facets, turns
the two differently). A full leg that leaves the band turning in the other sense (a capture
and an escape may reverse it) stays on the full equations, which need no sense: the band's
measure counts it inside.
"""

from __future__ import annotations

import math

import numpy as np

from tumble._typing import FloatArray
from tumble.averaging.triaxial import rotation_sense, sense_turn
from tumble.models.base import Crossing
from tumble.models.orbiting_body.inputs import Params
from tumble.rotations import matrix_to_quat, quat_normalize, quat_to_matrix
from tumble.unperturbed.euler_poinsot import polhode_point

__all__ = ["CAPTURE_MARGIN", "capture_band"]

CAPTURE_MARGIN = 8.0
"""The edge of the band in libration frequencies above the orbital rate: the full equations
take over while the relative rate is still several wells away, so that the phases chosen at
the hand-over do not decide a capture at once. Over eight attitudes of a 4 kg box whose full
runs were captured in 6: at 2, captured in 5, agreeing with the full run in 5 of 8; at 8,
captured in 6, agreeing in 6 of 8 (docs/theory/orbiting-body.md §9a)."""


def _rate(inertia: FloatArray, omega: FloatArray) -> float:
    """2T/L of the body rate ``omega`` (principal axes) [rad per model time unit]."""
    h = inertia * omega
    return float(omega @ h) / float(np.linalg.norm(h))


def capture_band(p: Params, sense: float = 1.0) -> Crossing:
    """The band of an orbiting body's hybrid run (module notes); in model time units. A full
    leg starts in the sense of rotation ``sense`` (:func:`tumble.averaging.rotation_sense`),
    the averaged run's."""
    assert p.orbit is not None  # an orbiting body has one
    inertia = np.asarray(p.inertia, dtype=float)
    i1, i2, i3 = sorted(inertia.tolist())
    n = p.orbit.mean_motion * p.T0
    edge = n + CAPTURE_MARGIN * n * math.sqrt(3.0 * (i3 - i1) / i2)
    # band: −1 at n, 0 on the edge, 1 as far above it (a sphere's: in units of n)
    width = edge - n if edge > n else n

    def band(z: FloatArray) -> float:
        rate = float(z[3]) * float(np.linalg.norm(z[:3]))  # 2T/L = r·L
        return (rate - edge) / width

    def band_full(y: FloatArray) -> float:
        omega = np.asarray(y[:3], dtype=float)
        if rotation_sense(inertia, omega) != sense:
            return -1.0  # the other sense: not one the averaged equations hold (module notes)
        return (_rate(inertia, omega) - edge) / width

    def to_full(t: float, z: FloatArray) -> FloatArray:
        L_xi = np.asarray(z[:3], dtype=float)
        L = float(np.linalg.norm(L_xi))
        T = 0.5 * float(z[3]) * L * L
        omega = polhode_point(inertia, L, T) @ sense_turn(inertia, L, T, sense)
        # The smallest rotation taking the body direction of L to L_ξ.
        from scipy.spatial.transform import Rotation  # only at a hand-over

        turn, _ = Rotation.align_vectors([L_xi], [inertia * omega])
        return np.concatenate([omega, matrix_to_quat(turn.as_matrix())])

    def to_mean(t: float, y: FloatArray, z_entry: FloatArray) -> FloatArray:
        omega = np.asarray(y[:3], dtype=float)
        h = inertia * omega
        L_xi = quat_to_matrix(quat_normalize(np.asarray(y[3:], dtype=float))) @ h
        return np.array([*L_xi, float(omega @ h) / float(L_xi @ L_xi)])

    return Crossing(
        band=band,
        band_full=band_full,
        to_full=to_full,
        to_mean=to_mean,
        label=f"gravity-gradient capture (rate < n + {CAPTURE_MARGIN:g} ω_lib)",
        chunk=2.0 * math.pi / n,  # an orbit between two looks at the band
    )
