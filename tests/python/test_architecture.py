"""The package's shape: stages that import one way, imports at the top, and clean lint, format and types."""

from __future__ import annotations

import ast
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PACKAGE = ROOT / "src" / "yoyogait"

# Optional or heavy dependencies that a module may import where it needs them (and only there).
LATE_IMPORTS_ALLOWED = {
    "ezc3d",
    "pylsl",
    "rclpy",
    "std_msgs",
    "geometry_msgs",
    "diagnostic_msgs",
    "rcl_interfaces",
    "sensor_msgs",
    "mocap4r2_msgs",
    "dask",
    "distributed",
    "optuna",
    "pandas",
    "tomli_w",
    "matplotlib",
    "PIL",
    "mobgap",
    "h5py",
    "scipy",  # scipy.signal alone is a second of every command's start
}

# The entry points, which import the commands (numpy, scipy, the core) under their Ctrl-C guard.
LATE_IMPORTS_ALLOWED_IN = {"yoyogait.cli", "yoyogait.__main__"}


def _module_name(path: Path) -> str:
    rel = path.relative_to(PACKAGE.parent).with_suffix("")
    parts = rel.parts[:-1] if rel.name == "__init__" else rel.parts
    return ".".join(parts)


def _modules() -> dict[str, Path]:
    return {_module_name(p): p for p in PACKAGE.rglob("*.py")}


def _resolve(module: str, is_package: bool, node: ast.ImportFrom) -> str:
    if node.level == 0:
        return node.module or ""
    base = module.split(".") if is_package else module.split(".")[:-1]
    base = base[: len(base) - (node.level - 1)]
    return ".".join(base + ([node.module] if node.module else []))


def _imports(modules: dict[str, Path]):
    """(importer, imported yoyogait module, node, at top level) for every import in the package."""
    for name, path in modules.items():
        tree = ast.parse(path.read_text())
        top = set(map(id, tree.body))
        is_package = path.name == "__init__.py"
        for node in ast.walk(tree):
            targets = []
            if isinstance(node, ast.Import):
                targets = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                base = _resolve(name, is_package, node)
                targets = [base] + [f"{base}.{a.name}" for a in node.names if f"{base}.{a.name}" in modules]
            for target in targets:
                yield name, target, node, id(node) in top


#: The stages by rank: a module may import from its own stage and from stages of a lower rank, never up
#: and never from a sibling of the same rank (evaluation, live and guidance know nothing of each other).
#: Rank 0 is what every stage shares (errors, output files, the native module, the Yoyo-model).
STAGE_RANKS = {
    "": 0,
    "io": 1,
    "synthetic": 2,
    "synthetic_conditions": 2.5,  # built on synthetic
    "pipeline": 3,
    "estimators": 4,
    "evaluation": 5,
    "live": 5,
    "ros2": 5,
    "guidance": 5,
    "cli": 6,
    "__main__": 7,
    "yoyogait": 7,
}


def _stage(module: str) -> str:
    """The stage of a module: its subpackage or stage module (yoyogait.io.c3d: io; yoyogait.synthetic:
    synthetic), "yoyogait" for the package itself, "" for the shared top-level modules."""
    parts = module.split(".")
    if len(parts) == 1:
        return "yoyogait"
    if parts[1] == "synthetic_imu":  # the synthetic lab's IMU: the same stage
        return "synthetic"
    return parts[1] if parts[1] in STAGE_RANKS else ""


def _layer_violations(modules: dict[str, Path]) -> list[str]:
    out = []
    for importer, target, _, _ in _imports(modules):
        if target not in modules or target == "yoyogait":
            continue
        a, b = _stage(importer), _stage(target)
        if a == b:
            continue
        if STAGE_RANKS[b] >= STAGE_RANKS[a]:
            out.append(f"{importer} ({a or 'shared'}) imports {target} ({b or 'shared'})")
    return sorted(set(out))


def test_every_stage_imports_only_from_stages_before_it():
    """io < synthetic < pipeline < estimators < evaluation, live, guidance < cli: no import goes up or sideways."""
    modules = _modules()
    assert set(STAGE_RANKS) - {"", "yoyogait"} >= {p.name for p in PACKAGE.iterdir() if (p / "__init__.py").is_file()}
    assert _layer_violations(modules) == []


def test_the_layer_check_catches_an_import_that_goes_up(tmp_path):
    """An io module that imports the pipeline, or evaluation importing live, is reported."""
    modules = _modules()
    fake_io = tmp_path / "io_up.py"
    fake_io.write_text("from ..pipeline import points\n")
    fake_eval = tmp_path / "eval_side.py"
    fake_eval.write_text("from ..live import live\n")
    modules = modules | {"yoyogait.io.io_up": fake_io, "yoyogait.evaluation.eval_side": fake_eval}
    found = _layer_violations(modules)
    assert any(v.startswith("yoyogait.io.io_up (io) imports yoyogait.pipeline") for v in found), found
    assert any(v.startswith("yoyogait.evaluation.eval_side (evaluation) imports yoyogait.live") for v in found), found


def test_no_import_cycles_between_modules():
    """No yoyogait module imports, directly or through others, a module that imports it back."""
    modules = _modules()
    graph: dict[str, set[str]] = {m: set() for m in modules}
    for importer, target, _, _ in _imports(modules):
        # Importing a.b.c runs a.b's __init__ first, so the importer depends on every package on the way.
        parts = target.split(".")
        for k in range(1, len(parts) + 1):
            dep = ".".join(parts[:k])
            if dep in modules and dep != importer and not importer.startswith(dep + "."):
                graph[importer].add(dep)
    state: dict[str, int] = {}
    stack: list[str] = []

    def visit(m: str) -> None:
        state[m] = 1
        stack.append(m)
        for d in sorted(graph[m]):
            if state.get(d) == 1:
                cycle = stack[stack.index(d) :] + [d]
                pytest.fail("import cycle: " + " -> ".join(cycle))
            if d not in state:
                visit(d)
        stack.pop()
        state[m] = 2

    for m in sorted(graph):
        if m not in state:
            visit(m)


def test_imports_sit_at_the_top_except_optional_dependencies():
    """Every import is at module level, except of an optional or heavy dependency where it is used (and
    in the entry points)."""
    late = []
    for name, path in _modules().items():
        if name in LATE_IMPORTS_ALLOWED_IN:
            continue
        tree = ast.parse(path.read_text())
        top = set(map(id, tree.body))
        for node in ast.walk(tree):
            if isinstance(node, (ast.Import, ast.ImportFrom)) and id(node) not in top:
                roots = {a.name.split(".")[0] for a in node.names} if isinstance(node, ast.Import) else None
                if isinstance(node, ast.ImportFrom):
                    roots = {(node.module or "").split(".")[0]} if node.level == 0 else {"yoyogait"}
                if not roots or not roots <= LATE_IMPORTS_ALLOWED:
                    late.append(f"{path.relative_to(ROOT)}:{node.lineno}")
    assert not late, "imports inside functions: " + ", ".join(late)


def _tool(name: str) -> str:
    exe = shutil.which(name) or str(Path(sys.executable).parent / name)
    if not Path(exe).exists():
        reason = f"{name} is not installed (pip install '.[test]' brings it)"
        if os.environ.get("CI"):
            pytest.fail(reason)
        pytest.skip(reason)
    return exe


def _run(cmd: list[str]) -> subprocess.CompletedProcess:
    return subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True)


def test_ruff_lint_is_clean():
    """ruff finds nothing to report in the package, the tests and the benchmarks."""
    proc = _run([_tool("ruff"), "check", "src", "tests", "bench", "examples"])
    assert proc.returncode == 0, proc.stdout[-4000:] + proc.stderr[-2000:]


def test_ruff_format_is_applied():
    """Every Python file is formatted as ruff format would write it."""
    proc = _run([_tool("ruff"), "format", "--check", "src", "tests", "bench", "examples"])
    assert proc.returncode == 0, proc.stdout[-4000:] + proc.stderr[-2000:]


def test_mypy_is_clean_on_the_package():
    """mypy finds no type error in src/yoyogait (settings in pyproject.toml)."""
    proc = _run([_tool("mypy"), "--cache-dir", str(ROOT / "build" / "mypy-cache")])
    assert proc.returncode == 0, proc.stdout[-4000:] + proc.stderr[-2000:]
