"""Type aliases shared by the modules that build CasADi expressions."""

from typing import Any, TypeAlias

Expr: TypeAlias = Any
"""A CasADi expression or value: SX, MX or DM (or a float where a formula accepts it).

CasADi's type stubs treat SX, MX and DM as unrelated classes, while every formula in scalf-opt is
written once for all three; the alias says so instead of a union that the stubs cannot follow."""
