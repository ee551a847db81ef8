"""Scenario and sweep files read as TOML, and the shipped templates, with nothing but the
standard library.

Kept apart from the validation (:mod:`tumble.io.scenario`, which loads the models) so that a
file that is missing, not UTF-8 or not TOML is reported at once, and ``tumble init`` answers
at once.
"""

from __future__ import annotations

import tomllib
from importlib import resources
from pathlib import Path
from typing import Any

from tumble.catalogue import CATALOGUE
from tumble.errors import ScenarioError, shorten

__all__ = ["read_file", "read_toml", "template"]


def read_toml(raw: bytes, where: str) -> dict[str, Any]:
    """A TOML document from its bytes; ScenarioError in one line for anything that is not
    UTF-8 TOML of sane depth."""
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise ScenarioError(
            f"{where}: not UTF-8 text (byte 0x{raw[exc.start]:02x} at position {exc.start})"
        ) from None
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ScenarioError(f"{where}: not valid TOML ({shorten(str(exc))})") from None
    except RecursionError:
        raise ScenarioError(f"{where}: arrays or tables nested too deeply") from None


def read_file(path: str | Path, what: str = "scenario") -> dict[str, Any]:
    """The TOML document in the file ``path`` (``what`` names it in errors: "scenario",
    "sweep file")."""
    try:
        raw = Path(path).read_bytes()
    except OSError as exc:
        raise ScenarioError(f"{path}: cannot read the {what} ({exc.strerror})") from None
    return read_toml(raw, str(path))


def template(model: str) -> str:
    """A commented example scenario for ``model`` (what ``tumble init`` prints): the
    ``template.toml`` of its package, ``tumble.models.<model>``."""
    if model not in CATALOGUE:
        raise ScenarioError(
            f"model = {shorten(repr(model), 60)} is not a known model "
            f"(allowed: {', '.join(sorted(CATALOGUE))})"
        )
    # Read as a file of the package tree: importing tumble.models would load numpy.
    found = resources.files("tumble").joinpath("models", model, "template.toml")
    return found.read_text("utf-8")
