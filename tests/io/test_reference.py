"""The key reference of the documentation is generated from the models' declarations."""

from __future__ import annotations

from files import ROOT

from tumble.io.reference import scenario_reference
from tumble.io.scenario import run_keys, schema_for
from tumble.models import MODELS
from tumble.models.base import Declaration


def test_the_committed_page_is_the_generated_one():
    """docs/scenario-keys.md is out of date: run python -m tumble.io.reference."""
    page = (ROOT / "docs" / "scenario-keys.md").read_text(encoding="utf-8")
    assert page == scenario_reference()


def test_every_declared_key_is_accepted_and_documented():
    """Each model's declared keys are the fields of its compiled schema, in the same order,
    and each appears in the reference."""
    page = scenario_reference()
    for name, model in MODELS.items():
        if model.scenario is None:
            continue
        for variant in model.scenario.variants:
            data = {"model": name, **({"physical": {}} if variant.physical else {})}
            schema = schema_for(data)
            assert schema is not None
            for section in variant.sections:
                if section.name:
                    fields = (
                        list(schema.model_fields[section.name].annotation.__args__[0].model_fields)
                        if not section.required
                        else list(schema.model_fields[section.name].annotation.model_fields)
                    )
                    assert fields == [k.name for k in section.keys], (name, section.name)
                for key in section.keys:
                    assert f"`{key.name}`" in page, (name, key.name)
            run = [k.name for k in run_keys(Declaration.of(model), variant)]
            assert set(_fields(schema.model_fields["run"].annotation)) == set(run)


def _fields(annotation):
    """The keys of a table's compiled model (an optional table is ``Model | None``)."""
    model = next(
        (a for a in getattr(annotation, "__args__", ()) if hasattr(a, "model_fields")),
        annotation,
    )
    return list(model.model_fields)
