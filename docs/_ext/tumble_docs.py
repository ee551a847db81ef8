"""tumble's own additions to the documentation build.

* ``.. tumble-cli::``: the reference of the ``tumble`` command, read from the typer app itself:
  for every command its usage, its description and a table of its arguments and options
  (names, type, default, meaning).
* Numbers in tables are never broken across lines: a token such as ``1.2e-03`` or ``−0.5``
  would otherwise wrap at its hyphen; each one is set in a span that does not wrap.
* The site's stylesheet (``_static/tumble.css``).
"""

from __future__ import annotations

import inspect
import re
import types
import typing
from pathlib import Path
from typing import Any

import typer
from docutils import nodes
from docutils.statemachine import StringList
from sphinx.application import Sphinx
from sphinx.transforms import SphinxTransform
from sphinx.util.docutils import SphinxDirective
from sphinx.util.nodes import nested_parse_with_titles

import tumble.cli

_TYPE_NAMES = {Path: "path", float: "number", int: "integer", str: "text", bool: "flag"}


def _type_name(annotation: Any) -> str:
    """The type of a parameter in words: ``path``, ``number``, ``one of: a, b``, …"""
    origin = typing.get_origin(annotation)
    args = [a for a in typing.get_args(annotation) if a is not type(None)]
    if origin in (typing.Union, types.UnionType) and len(args) == 1:
        return _type_name(args[0])
    if origin is list:
        return _type_name(args[0]) + ", repeatable"
    if origin is tuple and args and all(a is float for a in args):
        return f"{len(args)} numbers"
    if origin is typing.Literal:
        return "one of: " + ", ".join(f"`{a}`" for a in args)
    return _TYPE_NAMES.get(annotation, getattr(annotation, "__name__", str(annotation)))


def _cell(text: str) -> str:
    """One line of a list-table cell (help texts are written on several source lines)."""
    return " ".join(text.split()) or " "


def _parameter_rows(command: Any) -> list[tuple[str, str, str, str]]:
    rows = []
    for p in command.params:
        if getattr(p, "hidden", False):
            continue
        annotation = p.type_descriptor.annotation
        is_flag = getattr(p, "is_flag", False) or annotation is bool
        if p.opts and p.opts[0].startswith("-"):
            names = ", ".join(f"`{o}`" for o in p.opts + p.secondary_opts)
        else:
            names = f"`{p.name.upper()}`" + (" …" if p.nargs == -1 or p.multiple else "")
        kind = "flag" if is_flag else _type_name(annotation)
        if p.required:
            default = "required"
        elif is_flag:
            default = "on" if p.default else "off"
        elif p.default is None or p.default == []:
            default = "—"
        else:
            default = f"`{p.default}`"
        raw = _unescaped(p.help or "")
        help_text = _prose(_cell(raw))
        help_text = re.sub(r"\s*\[default: ([^\]]+)\]", "", help_text)
        m = re.search(r"\[default: ([^\]]+)\]", raw)
        if m:
            default = f"`{m.group(1)}`"
        rows.append((names, kind, default, help_text))
    return rows


def _unescaped(text: str) -> str:
    """A help text as written: the command line escapes its brackets from rich's markup."""
    return text.replace("\\[", "[")


def _prose(text: str) -> str:
    """A command's description as Markdown: options and file names set as code."""
    text = inspect.cleandoc(text).replace("\b\n", "")
    return re.sub(r"(?<![\w`])(--[a-z][a-z-]*)", r"`\1`", text)


class CliReference(SphinxDirective):
    """``tumble-cli``: one section per command of ``tumble``, in the app's order (the page is
    Markdown, so the directive writes Markdown for MyST to parse)."""

    def run(self) -> list[nodes.Node]:
        self.env.note_dependency(tumble.cli.__file__)  # rebuilt when the commands change
        group = typer.main.get_command(tumble.cli.app)
        lines: list[str] = []
        for name, command in group.commands.items():
            if command.hidden:
                continue
            positional = [p for p in command.params if not (p.opts and p.opts[0].startswith("-"))]
            usage = " ".join(
                ["tumble", name, "[OPTIONS]"]
                + [p.name.upper() + (" …" if p.nargs == -1 else "") for p in positional]
            )
            lines += [f"## `tumble {name}`", "", "```console", f"$ {usage}", "```", ""]
            lines += [*_prose(_unescaped(command.help or "")).splitlines(), ""]
            rows = _parameter_rows(command)
            if rows:
                lines += [
                    "```{list-table}",
                    ":header-rows: 1",
                    ":widths: 22 14 14 50",
                    "",
                    "* - argument or option",
                    "  - type",
                    "  - default",
                    "  - meaning",
                ]
                for row in rows:
                    lines += [f"* - {row[0]}"] + [f"  - {c}" for c in row[1:]]
                lines += ["```", ""]
        container = nodes.container()
        nested_parse_with_titles(self.state, StringList(lines, source="tumble.cli"), container)
        return container.children


# A token that a browser may break at a hyphen or minus sign and that holds a digit.
_BREAKABLE = re.compile(r"\S*\d\S*[-−‐]\S*|\S*[-−‐]\S*\d\S*")


SHORT_CELL = 14
"""A table cell this short (characters) is never wrapped: a number and its unit stay together."""


class _NumbersDoNotWrap(SphinxTransform):
    """Keep numbers in table cells whole: a short cell does not wrap at all, and in a longer
    one every number-like token with a hyphen is set in ``<span class="nowrap">``."""

    default_priority = 700

    def apply(self, **kwargs: Any) -> None:
        for entry in list(self.document.findall(nodes.entry)):
            if len(entry.astext()) <= SHORT_CELL:  # a number with its unit: "1.02 %", "15.7×"
                entry["classes"].append("nowrap")
                continue
            for text in list(entry.findall(nodes.Text)):
                parent = text.parent
                if isinstance(parent, (nodes.literal, nodes.math, nodes.inline)):
                    continue
                value = str(text)
                pieces: list[nodes.Node] = []
                last = 0
                for m in _BREAKABLE.finditer(value):
                    if m.start() > last:
                        pieces.append(nodes.Text(value[last : m.start()]))
                    pieces.append(nodes.inline(m.group(0), m.group(0), classes=["nowrap"]))
                    last = m.end()
                if not pieces:
                    continue
                if last < len(value):
                    pieces.append(nodes.Text(value[last:]))
                parent.replace(text, pieces)


def setup(app: Sphinx) -> dict[str, Any]:
    app.add_directive("tumble-cli", CliReference)
    app.add_transform(_NumbersDoNotWrap)
    app.add_css_file("tumble.css")
    return {"parallel_read_safe": True, "parallel_write_safe": True}
