"""The reference of the scenario keys, generated from the models' declarations.

``python -m tumble.io.reference > docs/scenario-keys.md`` writes the page; a test checks that
the committed page is the generated one.
"""

from __future__ import annotations

import json
from collections.abc import Iterable

from tumble.io.scenario import describe, run_keys
from tumble.models import MODELS, AnyModel
from tumble.models.base import Declaration
from tumble.models.schema import REQUIRED, Key, Section

__all__ = ["scenario_reference"]


def _default(key: Key) -> str:
    if key.default is REQUIRED:
        return "required"
    if key.default is None:
        return "—"
    return f"`{json.dumps(key.default, ensure_ascii=False)}`"


def _table(keys: Iterable[Key]) -> list[str]:
    rows = ["| key | value | default | meaning |", "|---|---|---|---|"]
    for k in keys:
        name = f"`{k.name}`" + (f" (or `{k.name}_deg`)" if k.angle else "")
        value, meaning = describe(k).replace("|", "\\|"), k.doc.replace("|", "\\|")
        rows.append(f"| {name} | {value} | {_default(k)} | {meaning} |")
    return rows


def _section(section: Section) -> list[str]:
    title = f"`[{section.name}]`" if section.name else "top-level keys"
    if not section.required:
        title += " (optional)"
    out = [f"#### {title}", ""]
    if section.doc:
        out += [section.doc[0].upper() + section.doc[1:] + ".", ""]
    return [*out, *_table(section.keys), ""]


def _model(model: AnyModel) -> list[str]:
    assert model.scenario is not None
    out = [f"## `{model.name}`", "", model.description[0].upper() + model.description[1:] + "."]
    if model.paper is not None:
        out += ["", f"{model.paper}."]
    out.append("")
    for variant in model.scenario.variants:
        if model.scenario.physical_only:
            which = "in SI units"
        else:
            which = "with `[physical]`" if variant.physical else "normalized"
        out += [f"### {which}: {variant.doc}" if variant.doc else f"### {which}", ""]
        for section in variant.sections:
            out += _section(section)
        out += ["#### `[run]`", "", *_table(run_keys(Declaration.of(model), variant)), ""]
    return out


def scenario_reference() -> str:
    """The page: every registered model's scenario keys, as Markdown."""
    out = [
        "# Scenario keys",
        "",
        "Every key a scenario file of each model can hold, generated from the keys the models",
        "declare (`tumble.models.schema`); `python -m tumble.io.reference` writes this page.",
        "Angles are radians; a key marked `(or <name>_deg)` also takes degrees. `[run]` gives",
        "either the end time (with `samples`) or the list of times.",
        "",
    ]
    for model in MODELS.values():
        if model.scenario is not None:
            out += _model(model)
    return "\n".join(out).rstrip() + "\n"


if __name__ == "__main__":  # pragma: no cover
    print(scenario_reference(), end="")
