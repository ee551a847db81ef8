"""Text a scenario may hold: printable, without control characters, checked before any of it
reaches a file system call or an import."""

from __future__ import annotations

import re
from collections.abc import Mapping
from typing import Any

from tumble.errors import ScenarioError, shorten

__all__ = ["check_text"]


_CONTROL = re.compile("[\x00-\x1f\x7f-\x9f]")
"""C0, DEL and C1: the control characters."""


def _control_character(text: str) -> str | None:
    """The first control character of ``text`` (C0, DEL, C1), as U+XXXX; None if none."""
    found = _CONTROL.search(text)
    return None if found is None else f"U+{ord(found.group()):04X}"


def check_text(data: Any, path: str = "") -> None:
    """Refuse a control character (NUL, a line break, an escape, …) in any key or text of a
    scenario: a name, a file reference, an epoch. One line naming the key; no such text
    reaches a file system call or an import (where a NUL byte is an internal error).

    Raises
    ------
    ScenarioError
        Naming the key (``torque[0].function``) and the character.
    """
    if isinstance(data, str):
        found = _control_character(data)
        if found is not None:
            raise ScenarioError(
                f"{shorten(path or 'scenario')} = {shorten(ascii(data), 60)}: holds the "
                f"control character {found} (allowed: printable text)"
            )
    elif isinstance(data, Mapping):
        for key, value in data.items():
            name = f"{path}.{key}" if path else str(key)
            found = _control_character(str(key))
            if found is not None:
                raise ScenarioError(
                    f"{shorten(ascii(name), 60)}: the key holds the control character {found} "
                    "(allowed: printable text)"
                )
            check_text(value, name)
    elif isinstance(data, list):
        for i, value in enumerate(data):
            check_text(value, f"{path}[{i}]")
