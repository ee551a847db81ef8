"""Docstring text that several functions share, written once.

Functions of one module often document a parameter, or an error, in the same words: the
moments (I1, I2, I3) and the state (L, T) of the Euler–Poinsot functions, the altitude of
the atmosphere's functions. :class:`DocSections` holds such blocks by name; a docstring asks
for one with a line that holds only ``{{name}}``, and the decorator puts the block there,
indented like that line, when the function is defined. ``help()`` and Sphinx read the whole
text.
"""

from __future__ import annotations

import re
import textwrap
from collections.abc import Callable
from typing import Any, TypeVar

__all__ = ["DocSections"]

_F = TypeVar("_F", bound=Callable[..., Any])

_SLOT = re.compile(r"^([ \t]*)\{\{(\w+)\}\}[ \t]*$", re.MULTILINE)
"""A line ``{{name}}`` (white space around it allowed): the place of block ``name``."""


class DocSections:
    """Named blocks of numpydoc text, and the decorator that writes them into docstrings.

    Parameters
    ----------
    **blocks : str
        The text of each block [numpydoc], by the name its slot lines use. Common leading
        white space and the blank lines around the text are removed, so a block may be
        written as an indented triple-quoted string.

    Notes
    -----
    A slot that names no block raises KeyError when the module is imported, so that a typo
    cannot reach the rendered text. Under ``python -OO`` docstrings are None and are left so.
    """

    def __init__(self, **blocks: str) -> None:
        self._blocks = {name: textwrap.dedent(text).strip("\n") for name, text in blocks.items()}

    def __call__(self, func: _F) -> _F:
        """``func`` with each slot line of its docstring replaced by its block.

        Parameters
        ----------
        func : callable
            A function (or a method, before ``classmethod`` wraps it).

        Returns
        -------
        callable
            ``func`` itself, its ``__doc__`` filled in.
        """
        if func.__doc__:
            func.__doc__ = _SLOT.sub(self._fill, func.__doc__)
        return func

    def _fill(self, slot: re.Match[str]) -> str:
        indent, name = slot.group(1), slot.group(2)
        return textwrap.indent(self._blocks[name], indent)
