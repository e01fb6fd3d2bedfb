"""What a model object builds once from itself and keeps: :class:`BuiltOnce`.

Pinocchio's split, model and data: a leg's physics (the model) owns what is derived from it
alone, its compiled per-sample kernels, its symbolic bound analyses, its built NLPs, so that they
live and die with it, and no module keeps a registry of them.
"""

from __future__ import annotations

from collections.abc import Callable, Hashable
from typing import Any, TypeVar

T = TypeVar("T")


class BuiltOnce:
    """A store of things built from their owner, each built on first use and kept.

    Not locked: a caller that builds symbolic CasADi functions holds
    :data:`~scalf_opt.energy.codegen.SYMBOLIC_LOCK` around :meth:`get`, as it must anyway.
    Pickled empty: compiled functions are rebuilt (from the machine's cache) where the owner
    lands, never shipped to another process.
    """

    def __init__(self) -> None:
        self._built: dict[Hashable, Any] = {}

    def get(self, key: Hashable, build: Callable[[], T]) -> T:
        """The thing under ``key``, built by ``build()`` the first time."""
        if key not in self._built:
            self._built[key] = build()
        return self._built[key]

    def __len__(self) -> int:
        return len(self._built)

    def __getstate__(self) -> dict[str, Any]:
        return {}

    def __setstate__(self, state: dict[str, Any]) -> None:
        self._built = {}
