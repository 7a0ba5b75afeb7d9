"""examples/guidance: the C++ controller builds against an installed yoyogait and guides on its estimate."""

from __future__ import annotations

import csv
import io
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[3]
BUILD = ROOT / "build" / "pytest"


def _cmake() -> str:
    exe = shutil.which("cmake") or str(Path(sys.executable).parent / "cmake")
    if not Path(exe).exists() and not shutil.which(exe):
        pytest.fail("cmake is needed to build the C++ example (pip install '.[test]' brings it)")
    return exe


def _generator() -> list[str]:
    return ["-G", "Ninja"] if shutil.which("ninja") else []


def _run(cmd, **kw) -> subprocess.CompletedProcess:
    proc = subprocess.run([str(c) for c in cmd], capture_output=True, text=True, **kw)
    if proc.returncode != 0:
        pytest.fail(f"{' '.join(map(str, cmd))} failed:\n{proc.stdout[-4000:]}\n{proc.stderr[-4000:]}")
    return proc


@pytest.fixture(scope="module")
def controller(tmp_path_factory) -> Path:
    """examples/guidance built against yoyogait installed into a temporary prefix."""
    cmake = _cmake()
    tmp = tmp_path_factory.mktemp("guidance-example")
    build, prefix, example = BUILD / "guidance-install", tmp / "prefix", tmp / "example"
    _run([cmake, "-S", ROOT, "-B", build, *_generator(), f"-DCMAKE_INSTALL_PREFIX={prefix}"])
    _run([cmake, "--install", build])
    _run(
        [
            cmake,
            "-S",
            ROOT / "examples" / "guidance",
            "-B",
            example,
            *_generator(),
            f"-DCMAKE_PREFIX_PATH={prefix}",
            "-DCMAKE_BUILD_TYPE=Release",
        ]
    )
    _run([cmake, "--build", example])
    return next(example.rglob("guide_controller"))


def _rows(text: str) -> dict[str, np.ndarray]:
    table = list(csv.DictReader(io.StringIO(text)))
    return {k: np.array([float(r[k]) for r in table]) for k in table[0]}


def test_the_controller_follows_a_synthetic_walk_at_its_speed(controller):
    """On the built-in SYNTHETIC walk (1.2 m/s) the robot ends up flying at the walking speed, pulling (taut cable),
    with the estimate walking and valid, the velocity it uses free of the step oscillation, and none fed forward
    while the estimate is not valid."""
    out = _rows(_run([controller, "--synthetic"]).stdout)
    late = out["t_s"] > 8.0
    assert len(out["t_s"]) == 1501 and np.all(out["walking"][late] == 1)
    assert abs(np.mean(out["robot_vx_mps"][late]) - 1.2) < 0.05
    assert np.all(out["tension_n"][late] > 0) and np.all(np.isfinite(out["tension_n"]))
    assert np.std(out["vh_hat_x_mps"][late]) < 0.05  # the handle's own oscillation is 2 pi 1.8 Hz x 2 cm ~ 0.23 m/s
    # The velocity is fed forward only from an estimate that may be used: none while it is acquiring.
    held = out["valid"] == 0
    assert np.all(out["valid"][late] == 1) and held[:50].all()
    assert np.all(out["vh_hat_x_mps"][held] == 0) and np.all(out["vh_hat_y_mps"][held] == 0)


def test_the_controller_reads_frames_on_stdin(controller):
    """Frames on standard input get one output line each (the header and a comment skipped); a bad option is exit 2."""
    lines = ["t_s,x_m,y_m,z_m", "# standing"] + [f"{k / 100:.2f},{0.0:.3f},0.0,1.0" for k in range(200)]
    proc = _run([controller], input="\n".join(lines) + "\n")
    rows = proc.stdout.strip().splitlines()
    assert rows[0].startswith("t_s,walking") and len(rows) == 201
    bad = subprocess.run([str(controller), "--fast"], capture_output=True, text=True)
    assert bad.returncode == 2 and len(bad.stderr.strip().splitlines()) == 1
