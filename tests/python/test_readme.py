"""The README's Python examples run as a new user types them, on a real walk in place of walk.c3d."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]

#: A shared recording with the example's pelvis points (RASI, LASI, SACR).
WALK = "c3d_org_samples/sample10_TYPE-3.c3d"


def _python_blocks() -> list[str]:
    return re.findall(r"^```python\n(.*?)^```", (ROOT / "README.md").read_text(), flags=re.S | re.M)


def test_the_readmes_python_examples_run_in_order(datasets_dir, tmp_path, monkeypatch):
    """Every ```python block of the README runs after the ones before it (one session, as a reader pastes them),
    reading the real walk as walk.c3d, and writes the files it says it writes."""
    blocks = _python_blocks()
    assert len(blocks) >= 3 and "yoyogait.read(" in blocks[0]
    (tmp_path / "walk.c3d").symlink_to(datasets_dir / WALK)
    monkeypatch.chdir(tmp_path)
    # The one name the IMU line takes from the reader's own sensor: a sample at rest.
    scope: dict = {"acc_mps2": np.array([0.0, 0.0, 9.81]), "gyr_rad_s": np.zeros(3)}
    for n, block in enumerate(blocks):
        try:
            exec(compile(block, f"README.md python block {n + 1}", "exec"), scope)  # noqa: S102 (the README's own code)
        except Exception as exc:  # noqa: BLE001 (name the block that failed)
            pytest.fail(f"README.md python block {n + 1} raised {type(exc).__name__}: {exc}")
    written = [name for name in re.findall(r"[\"']([\w.]+\.(?:png|toml|csv))[\"']", "".join(blocks))]
    assert written and all((tmp_path / name).is_file() for name in written), written
