"""User functions named by a scenario (``torque = "user_torques:bdot"``): loaded from a file,
explicitly, one module per file.

A scenario that names a function runs that code. tumble therefore loads it only

* from a Python file: ``"name:function"`` is the file ``name.py`` in the scenario's folder,
  ``"path/to/file.py:function"`` a file at a path relative to that folder; or
* from an importable module the user allowed by name (``--allow-module NAME``, the
  ``allow_modules`` argument of :func:`tumble.load_scenario`).

A file is loaded by its path, under a module name made of a hash of its resolved path and
contents (``tumble_user_<hash>_<stem>``): two scenarios whose folders both hold a
``user_torques.py`` get their own functions in one process or on one Dask worker, and an
edited file is loaded anew instead of served stale from ``sys.modules``.

Nothing of a user's file runs before the user has been told: :func:`user_function` reads the
file's syntax tree only (a missing function, or a file that is not Python, is refused without
running it) and returns a :class:`UserFunction` that runs nothing until it is first called or
:meth:`UserFunction.load` is called, which the scenario loader does once the whole scenario
has been validated and the caller has been shown what runs
(:func:`tumble.io.scenario.load_user_code`). A :class:`UserFunction` pickles as its file and
name, so a Dask worker loads the file itself.
"""

from __future__ import annotations

import ast
import hashlib
import importlib
import importlib.util
import sys
from collections.abc import Callable, Iterable
from pathlib import Path
from types import ModuleType
from typing import Any

from tumble.errors import ScenarioError, shorten

__all__ = ["UserFunction", "check_defines", "user_function"]


def _module_from_file(path: Path, where: str) -> ModuleType:
    """The module of ``path`` under its unique name (loaded once per path and contents, from
    exactly the contents read)."""
    data = path.read_bytes()
    digest = hashlib.sha256(str(path).encode() + b"\0" + data).hexdigest()[:16]
    name = f"tumble_user_{digest}_{path.stem.replace('-', '_')}"
    module = sys.modules.get(name)
    if module is not None:
        return module
    found = importlib.util.spec_from_file_location(name, path)
    if found is None or found.loader is None:
        raise ScenarioError(f"{where}: {path} is not a Python file")
    module = importlib.util.module_from_spec(found)
    sys.modules[name] = module
    # The file's own imports of its neighbours (``import helpers``) resolve in its folder.
    sys.path.insert(0, str(path.parent))
    try:
        # The bytes read above, compiled here: the loader would take a cached .pyc instead when
        # the file was rewritten within the same second at the same size (an edited value), and
        # run the old code; nothing is written into the user's folder either.
        exec(compile(data, str(path), "exec"), module.__dict__)
    except BaseException as exc:
        del sys.modules[name]
        if not isinstance(exc, Exception):
            raise
        raise ScenarioError(
            f"{where}: loading {path} failed ({type(exc).__name__}: {shorten(exc)})"
        ) from None
    finally:
        sys.path.remove(str(path.parent))
    return module


def _bound(statements: list[ast.stmt]) -> tuple[set[str], bool]:
    """The names that ``statements`` (a module's top level) bind, and whether a
    ``from … import *`` among them may bind any other. Compound statements (``if``, ``try``,
    ``with``, loops) are looked into, function and class bodies are not."""
    names: set[str] = set()
    star = False
    for node in statements:
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef):
            names.add(node.name)
            continue
        if isinstance(node, ast.Import | ast.ImportFrom):
            for alias in node.names:
                if alias.name == "*":
                    star = True
                else:
                    names.add(alias.asname or alias.name.split(".")[0])
            continue
        # Assignments (also unpacking, annotated, augmented, walrus, loop targets, ``with …
        # as``) at any depth of this statement outside nested functions and classes.
        stack: list[ast.AST] = [node]
        while stack:
            item = stack.pop()
            if isinstance(item, ast.Name) and isinstance(item.ctx, ast.Store):
                names.add(item.id)
            for child in ast.iter_child_nodes(item):
                if isinstance(child, ast.stmt):
                    continue  # nested statements: looked at below as statements
                stack.append(child)
        for block in ("body", "orelse", "finalbody", "handlers"):
            inner = getattr(node, block, None)
            if isinstance(inner, list) and inner:
                found, any_star = _bound(
                    [
                        s
                        for h in inner
                        for s in (h.body if isinstance(h, ast.ExceptHandler) else [h])
                    ]
                )
                names |= found
                star = star or any_star
        for case in getattr(node, "cases", ()):  # match statements
            found, any_star = _bound(case.body)
            names |= found
            star = star or any_star
    return names, star


def check_defines(path: Path, function: str, where: str) -> None:
    """Refuse a file that is not Python or binds no top-level ``function``, from its syntax
    tree alone: nothing of the file runs.

    Parameters
    ----------
    path : Path
        The user's file.
    function : str
        The name the scenario gives.
    where : str
        The scenario key and value, for messages.

    Raises
    ------
    ScenarioError
        The file cannot be read, is not valid Python, or binds no such name (a ``def``, an
        assignment or an import at its top level).
    """
    try:
        tree = ast.parse(path.read_bytes(), filename=str(path))
    except (SyntaxError, ValueError) as exc:  # ValueError: a NUL byte in the source
        line = getattr(exc, "lineno", None)
        at = f" at line {line}" if line else ""
        detail = exc.msg if isinstance(exc, SyntaxError) else str(exc)
        raise ScenarioError(
            f"{where}: {path} is not valid Python{at} ({type(exc).__name__}: {shorten(detail)})"
        ) from None
    except OSError as exc:
        raise ScenarioError(f"{where}: cannot read {path} ({shorten(exc)})") from None
    names, star = _bound(tree.body)
    if function not in names and not star:
        raise ScenarioError(f"{where}: {path} has no function {function}")


class UserFunction:
    """A function of a user's file or allowed module, loaded on first use.

    Parameters
    ----------
    reference : str
        As written in the scenario (for messages).
    function : str
        The function's name in its module.
    path : Path, optional
        The file to load (absolute).
    module : str, optional
        Instead of a file: an importable module the user allowed.
    where : str
        The scenario key, for messages.
    """

    def __init__(
        self,
        reference: str,
        function: str,
        *,
        path: Path | None = None,
        module: str | None = None,
        where: str = "torque",
    ) -> None:
        self.reference, self.function, self.path, self.module, self.where = (
            reference,
            function,
            path,
            module,
            where,
        )
        self._loaded: Callable[..., Any] | None = None

    @property
    def origin(self) -> str:
        """What runs: the file's path, or ``module NAME``."""
        return str(self.path) if self.path is not None else f"module {self.module}"

    def load(self) -> Callable[..., Any]:
        """Load the file (or import the allowed module) and return the function."""
        if self._loaded is not None:
            return self._loaded
        where = f"{self.where} = {shorten(repr(self.reference))}"
        if self.path is not None:
            mod = _module_from_file(self.path, where)
        else:
            assert self.module is not None
            try:
                mod = importlib.import_module(self.module)
            except Exception as exc:
                raise ScenarioError(
                    f"{where}: cannot import {self.module} ({type(exc).__name__}: {shorten(exc)})"
                ) from None
        function = getattr(mod, self.function, None)
        if not callable(function):
            raise ScenarioError(f"{where}: {self.origin} has no function {self.function}")
        self._loaded = function
        return function

    def __call__(self, *args: Any) -> Any:
        return self.load()(*args)

    @property
    def __wrapped__(self) -> Callable[..., Any]:
        """The loaded function (``inspect.unwrap`` reaches it: a numba function is then run
        compiled, :meth:`tumble.torques.UserTorque.compiled_terms`)."""
        return self.load()

    def __reduce__(self) -> tuple[Any, ...]:
        return (_rebuild, (self.reference, self.function, self.path, self.module, self.where))

    def __repr__(self) -> str:
        return f"UserFunction({self.reference!r} from {self.origin})"


def _rebuild(
    reference: str, function: str, path: Path | None, module: str | None, where: str
) -> UserFunction:
    return UserFunction(reference, function, path=path, module=module, where=where)


def user_function(
    reference: str, base: Path, where: str, allow_modules: Iterable[str] = ()
) -> UserFunction:
    """The function a scenario names, not yet loaded.

    Parameters
    ----------
    reference : str
        ``"name:function"`` (the file ``name.py`` in ``base``), ``"path/file.py:function"``
        (relative to ``base``), or ``"module:function"`` for a module in ``allow_modules``.
    base : Path
        The scenario's folder.
    where : str
        The scenario key, for messages.
    allow_modules : iterable of str
        Importable modules the user allowed by name.

    Raises
    ------
    ScenarioError
        Malformed, naming neither a file beside the scenario nor an allowed module, or naming
        a file that does not define the function (read from its syntax tree, not run).
    """
    target, sep, name = reference.rpartition(":")
    shown = f"{where} = {shorten(repr(reference))}"
    if any(not c.isprintable() for c in reference):  # a NUL byte would reach the file system
        raise ScenarioError(f"{shown}: control characters are not allowed in a reference")
    if not sep or not target or not name.isidentifier():
        raise ScenarioError(
            f'{shown}: expected "file:function" (a Python file beside the scenario)'
        )
    if target in set(allow_modules):
        return UserFunction(reference, name, module=target, where=where)
    relative = Path(target if target.endswith(".py") else target.replace(".", "/") + ".py")
    path = (base / relative).resolve()
    if not path.is_file():
        raise ScenarioError(
            f"{shown}: no file {relative} in {base} (a torque function is loaded from a Python "
            f"file beside the scenario; an installed module runs only with --allow-module "
            f"{shorten(target, 40)})"
        )
    check_defines(path, name, shown)
    return UserFunction(reference, name, path=path, where=where)
