"""A run's attitude as CCSDS Attitude Data Messages (ADM version 2, CCSDS 504.0-B-2), in KVN.

``<method>.aem``: an Attitude Ephemeris Message of every method whose run carries the
attitude quaternion (a full run's ``q0…q3``), one data line per sample; ``initial.apm``: an
Attitude Parameter Message of the attitude and body rate at t = 0.

Frames and conventions. The ADM's quaternion "from frame A to frame B" is that of the
rotation carrying A's basis vectors onto B's, X_B = M_BA X_A, written Q1 Q2 Q3 QC with the
scalar QC last (Annex F2 of the standard). tumble's attitude quaternion q = (q0, q1, q2, q3)
is scalar first and maps body components to inertial ones, v_inertial = R(q) v_body, so
M_BA = R(q)ᵀ with A the inertial frame and B the body: Q1 Q2 Q3 QC = q1 q2 q3 q0, with no
change of sign. REF_FRAME_A is ``TEME``: the orbiting body's inertial axes are the Earth's
equator and the equinox from which the Greenwich mean sidereal angle is counted (those of an
SGP4 orbit), at the epoch, held fixed over the run (tumble neglects precession and nutation);
REF_FRAME_B is ``SC_BODY_1``, the body axes the scenario gave its inertia in.

Epochs are absolute (the standard has no relative time tags in an AEM or APM): UTC, the
scenario's ``orbit.epoch`` plus the run's time t in SI seconds (no leap second is inserted
within the span). A run without an epoch (a normalised scenario, or a physical one of a model
without an orbit) has no AEM: :func:`check_ccsds` refuses it before the computation.
"""

from __future__ import annotations

import math
from datetime import UTC, datetime, timedelta
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from tumble._version import __version__
from tumble.analysis import RunResult
from tumble.errors import ScenarioError

__all__ = ["ATTITUDE", "REF_FRAME_A", "REF_FRAME_B", "aem_text", "apm_text", "ccsds_outputs",
           "check_ccsds"]  # fmt: skip

ATTITUDE = ("q0", "q1", "q2", "q3")
"""The columns of tumble's attitude quaternion: scalar first, body → inertial."""

REF_FRAME_A = "TEME"
"""The inertial frame: the Earth's equator and the equinox of the Greenwich mean sidereal
angle, at the epoch (SANA's True Equator, Mean Equinox)."""

REF_FRAME_B = "SC_BODY_1"
"""The body frame: the scenario's body axes."""

_ORIGINATOR = "TUMBLE"
_CENTER = "EARTH"


def _has_attitude(columns: Any) -> bool:
    return all(name in columns for name in ATTITUDE)


def check_ccsds(request: Any) -> None:
    """Refuse, before the computation, a run that cannot give an AEM: one without an epoch or
    without a method carrying the attitude.

    Parameters
    ----------
    request : RunRequest
        The scenario's run request (``request.params``, ``request.scaling``,
        ``request.methods``).

    Raises
    ------
    ScenarioError
        If the run has no absolute epoch (``orbit.epoch`` of an orbiting body given in SI) or
        none of its methods writes the attitude quaternion ``q0…q3``.
    """
    if request.scaling is None or not getattr(request.params, "epoch", ""):
        raise ScenarioError(
            f"--aem: model {request.model.name} has no absolute epoch (orbit.epoch of an "
            "orbiting_body scenario in SI units); the CCSDS AEM has no relative times"
        )
    columns = request.model.columns
    if not any(_has_attitude({c.name for c in columns(request.params, m)})
               for m in request.methods):  # fmt: skip
        raise ScenarioError(
            f'--aem: run.methods = {list(request.methods)} carries no attitude (q0…q3): add "full"'
        )


def _epoch(text: str) -> datetime:
    when = datetime.fromisoformat(text.replace("Z", "+00:00"))
    return when.replace(tzinfo=UTC) if when.tzinfo is None else when.astimezone(UTC)


def epochs(epoch: str, t_s: np.ndarray) -> list[str]:
    """ISO 8601 UTC time tags (``YYYY-MM-DDThh:mm:ss.fffffffff``, the form of 6.8.9 of the
    standard) of the times ``t_s`` [s] after ``epoch``, to the nanosecond.

    Parameters
    ----------
    epoch : str
        ISO 8601 time of t = 0 (``orbit.epoch``), UTC unless it names an offset.
    t_s : ndarray
        Times after it [s].

    Returns
    -------
    list of str
    """
    start = _epoch(epoch)
    base = start.replace(microsecond=0)
    tags = []
    for t in np.asarray(t_s, dtype=float):
        ns = round(float(t) * 1e9) + start.microsecond * 1000
        seconds, frac = divmod(ns, 1_000_000_000)
        when = base + timedelta(seconds=seconds)
        tags.append(f"{when:%Y-%m-%dT%H:%M:%S}.{frac:09d}")
    return tags


def _number(x: float) -> str:
    """A real in the standard's floating-point notation (6.8.4.2): 16 significant digits,
    the mantissa's point in second position, never ``-0``."""
    return f"{float(x) + 0.0:.15e}"


def _header(kind: str, creation: datetime, comments: list[str]) -> list[str]:
    return [
        f"CCSDS_{kind}_VERS = 2.0",
        *(f"COMMENT {c}" for c in comments),
        f"CREATION_DATE = {creation.astimezone(UTC):%Y-%m-%dT%H:%M:%S}",
        f"ORIGINATOR = {_ORIGINATOR}",
        "",
    ]


def _object_name(source: str) -> str:
    """The scenario's name as OBJECT_NAME (a text value is all upper case, 6.8.6)."""
    name = Path(source).stem.upper() if source else "UNKNOWN"
    return "_".join(name.split()) or "UNKNOWN"


def _comments(result: RunResult, source: str, method: str) -> list[str]:
    return [
        f"tumble {__version__}, model {result.request.model.name}, method {method}, "
        f"scenario {Path(source).name}",
        f"{REF_FRAME_A}: the Earth's equator and the equinox of the Greenwich mean sidereal "
        "angle at the epoch, held fixed (precession and nutation neglected)",
        f"{REF_FRAME_B}: the scenario's body axes; quaternion from {REF_FRAME_A} to "
        f"{REF_FRAME_B}, X_B = M_BA X_A: Q1 Q2 Q3 QC = tumble's q1 q2 q3 q0",
    ]


def aem_text(
    ds: xr.Dataset,
    scaling: Any,
    epoch: str,
    *,
    object_name: str = "UNKNOWN",
    comments: tuple[str, ...] | list[str] = (),
    creation: datetime | None = None,
) -> str:
    """An AEM (KVN, version 2.0) of a run's attitude: one segment, ATTITUDE_TYPE =
    QUATERNION, a line ``EPOCH Q1 Q2 Q3 QC`` per sample.

    Parameters
    ----------
    ds : xarray.Dataset
        A method's run with the columns ``q0…q3`` (scalar first, body → inertial) along
        ``tau`` (the model's time).
    scaling : Scaling
        The scenario's scales: ``time_from_tau`` gives t [s].
    epoch : str
        ISO 8601 UTC time of t = 0.
    object_name : str
        OBJECT_NAME (OBJECT_ID is UNKNOWN).
    comments : sequence of str
        Header comments.
    creation : datetime, optional
        CREATION_DATE (default: now).

    Returns
    -------
    str
    """
    tags = epochs(epoch, scaling.time_from_tau(ds["tau"].values))
    q = np.column_stack([ds[c].values for c in ATTITUDE])
    lines = _header("AEM", creation or datetime.now(UTC), list(comments))
    lines += [
        "META_START",
        f"OBJECT_NAME = {object_name}",
        "OBJECT_ID = UNKNOWN",
        f"CENTER_NAME = {_CENTER}",
        f"REF_FRAME_A = {REF_FRAME_A}",
        f"REF_FRAME_B = {REF_FRAME_B}",
        "TIME_SYSTEM = UTC",
        f"START_TIME = {tags[0]}",
        f"STOP_TIME = {tags[-1]}",
        "ATTITUDE_TYPE = QUATERNION",
        "META_STOP",
        "",
        "DATA_START",
        *(
            f"{tag} {_number(q1)} {_number(q2)} {_number(q3)} {_number(q0)}"
            for tag, (q0, q1, q2, q3) in zip(tags, q, strict=True)
        ),
        "DATA_STOP",
    ]
    return "\n".join(lines) + "\n"


def apm_text(
    ds: xr.Dataset,
    scaling: Any,
    epoch: str,
    *,
    object_name: str = "UNKNOWN",
    comments: tuple[str, ...] | list[str] = (),
    creation: datetime | None = None,
) -> str:
    """An APM (KVN, version 2.0) of a run's first sample: the attitude quaternion and, where
    the run has them, the body rates ``omega1…3`` as ANGVEL_X…Z [deg/s] in the body frame.

    Parameters
    ----------
    ds, scaling, epoch, object_name, comments, creation
        As in :func:`aem_text`; ``omega1…3`` are in rad per unit of the model's time.

    Returns
    -------
    str
    """
    tag = epochs(epoch, scaling.time_from_tau(ds["tau"].values[:1]))[0]
    q0, q1, q2, q3 = (float(ds[c].values[0]) for c in ATTITUDE)
    lines = _header("APM", creation or datetime.now(UTC), list(comments))
    lines += [
        f"OBJECT_NAME = {object_name}",
        "OBJECT_ID = UNKNOWN",
        f"CENTER_NAME = {_CENTER}",
        "TIME_SYSTEM = UTC",
        "",
        f"EPOCH = {tag}",
        "",
        "QUAT_START",
        f"REF_FRAME_A = {REF_FRAME_A}",
        f"REF_FRAME_B = {REF_FRAME_B}",
        f"Q1 = {_number(q1)}",
        f"Q2 = {_number(q2)}",
        f"Q3 = {_number(q3)}",
        f"QC = {_number(q0)}",
        "QUAT_STOP",
    ]
    if all(f"omega{i}" in ds for i in (1, 2, 3)):
        # ω [rad/τ] → deg/s: dτ/dt from the scaling (t = T0 τ).
        per_s = 1.0 / float(scaling.time_from_tau(np.array([1.0]))[0])
        w = [math.degrees(float(ds[f"omega{i}"].values[0]) * per_s) for i in (1, 2, 3)]
        lines += [
            "",
            "ANGVEL_START",
            f"REF_FRAME_A = {REF_FRAME_A}",
            f"REF_FRAME_B = {REF_FRAME_B}",
            f"ANGVEL_FRAME = {REF_FRAME_B}",
            *(f"ANGVEL_{axis} = {_number(x)} [deg/s]" for axis, x in zip("XYZ", w, strict=True)),
            "ANGVEL_STOP",
        ]
    return "\n".join(lines) + "\n"


def ccsds_outputs(
    result: RunResult, source: str, *, creation: datetime | None = None
) -> dict[str, bytes]:
    """File name → content of a run's CCSDS messages: ``<method>.aem`` of every method that
    carries the attitude, ``initial.apm`` of the first one's state at t = 0.

    Parameters
    ----------
    result : RunResult
        A run that :func:`check_ccsds` accepted.
    source : str
        The scenario's file (its name is the OBJECT_NAME).
    creation : datetime, optional
        CREATION_DATE of every message (default: now).

    Returns
    -------
    dict of str to bytes
    """
    req = result.request
    check_ccsds(req)
    creation = creation or datetime.now(UTC)
    name = _object_name(source)
    files: dict[str, bytes] = {}
    for method, ds in result.datasets.items():
        if not _has_attitude(ds):
            continue
        notes = _comments(result, source, method)
        for file, text in (("aem", aem_text), ("apm", apm_text)):
            path = f"{method}.aem" if file == "aem" else "initial.apm"
            if path not in files:
                files[path] = text(ds, req.scaling, req.params.epoch, object_name=name,
                                   comments=notes, creation=creation).encode()  # fmt: skip
    return files
