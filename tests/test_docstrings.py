"""Shared docstring blocks (tumble._docstrings): filled in where asked, never left as a slot."""

import importlib
import inspect
import pkgutil

import pytest

import tumble
from tumble._docstrings import DocSections


def test_slot_is_replaced_by_its_block_indented_like_it():
    doc = DocSections(
        h="""
        h : float
            Altitude [m].
        """
    )

    @doc
    def f(h):
        """Value at h.

        Parameters
        ----------
        {{h}}
        """

    assert f.__doc__ == (
        "Value at h.\n\n        Parameters\n        ----------\n"
        "        h : float\n            Altitude [m].\n        "
    )


def test_unknown_slot_fails_at_definition():
    with pytest.raises(KeyError):

        @DocSections(h="h : float")
        def f(h):
            """{{height}}"""


def _modules():
    for info in pkgutil.walk_packages(tumble.__path__, "tumble."):
        if info.name.startswith(("tumble.unperturbed", "tumble.entry")):
            yield importlib.import_module(info.name)


@pytest.mark.parametrize("module", list(_modules()), ids=lambda m: m.__name__)
def test_no_docstring_keeps_a_slot(module):
    """A slot written without the decorator would reach help() and the documentation."""
    objects = [module, *vars(module).values()]
    for obj in list(objects):
        if inspect.isclass(obj):
            objects.extend(vars(obj).values())
    for obj in objects:
        doc = getattr(getattr(obj, "__func__", obj), "__doc__", None)
        assert not (isinstance(doc, str) and "{{" in doc), getattr(obj, "__qualname__", obj)
