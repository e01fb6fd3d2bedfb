"""The package's floors: every module imports only from its own package or the floors below.

The layer order is the data flow (README, "Code layout"). Imports are read from the source with
``ast``, so a new module is checked the moment it exists; an import inside ``if TYPE_CHECKING:``
counts too (types flow the same way as data).
"""

import ast
import subprocess
import sys
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[2] / "scalf_opt"

LAYERS: tuple[tuple[str, ...], ...] = (
    (
        "errors",
        "types",
        "files",
        "tables",
        "interrupts",
        "heartbeat",
        "blas_kernels",
        "workers",
        "version",
    ),
    ("model",),
    ("actuators",),
    ("robots",),
    ("locomotion",),
    ("energy",),
    ("optimize",),
    ("io",),
    ("viz",),
    ("studies", "sim", "logs"),
    ("cli", "__init__", "__main__", "api"),
)
"""Bottom to top. Packages in one tuple share a floor but may not import each other, except on
the foundation (errors, types, files, tables, interrupts, heartbeat, blas_kernels, workers,
version) and the top floor (the command line and the public API), which are one piece each."""

HEAVY_OPTIONAL = {
    "matplotlib": ("viz",),
    "meshcat": ("viz",),
    "mujoco": ("sim",),
    "dask": ("studies",),
}
"""Optional heavy libraries and the only packages that may import them."""


def top_package(path: Path) -> str:
    relative = path.relative_to(PACKAGE)
    return relative.parts[0].removesuffix(".py")


def floor(package: str) -> int:
    for i, names in enumerate(LAYERS):
        if package in names:
            return i
    raise AssertionError(f"scalf_opt.{package} is in no layer: add it to LAYERS (and the README)")


def imports(path: Path) -> list[str]:
    tree = ast.parse(path.read_text(encoding="utf-8"))
    out = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            out += [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            out.append(node.module)
            out += [f"{node.module}.{alias.name}" for alias in node.names]
    return out


MODULES = sorted(PACKAGE.rglob("*.py"))


@pytest.mark.parametrize("path", MODULES, ids=lambda p: str(p.relative_to(PACKAGE)))
def test_imports_go_down_the_floors(path):
    own = top_package(path)
    own_floor = floor(own)
    for name in imports(path):
        parts = name.split(".")
        if parts[0] == "scalf_opt" and len(parts) > 1:
            target = parts[1]
            if target == "__version__":
                continue
            target_floor = floor(target)
            same_piece = target == own or own_floor in (0, len(LAYERS) - 1)
            assert target_floor < own_floor or (target_floor == own_floor and same_piece), (
                f"{path.relative_to(PACKAGE)} imports {name}: floor {LAYERS[target_floor]} is "
                f"not below {LAYERS[own_floor]}"
            )
        elif parts[0] in HEAVY_OPTIONAL:
            assert own in HEAVY_OPTIONAL[parts[0]], (
                f"{path.relative_to(PACKAGE)} imports {parts[0]}, which only "
                f"{HEAVY_OPTIONAL[parts[0]]} may import"
            )


def test_the_command_line_starts_without_the_heavy_libraries():
    code = (
        "import sys, scalf_opt.cli; "
        "print(sorted({m.split('.')[0] for m in sys.modules} & "
        "{'casadi', 'pinocchio', 'matplotlib', 'scipy', 'meshcat', 'mujoco', 'dask'}))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"
