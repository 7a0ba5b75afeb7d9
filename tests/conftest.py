"""Shared fixtures: the project root and the real recordings in ../shared/datasets."""

from __future__ import annotations

import json
import os
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
# The independent numpy references and the corrupt-file generator, shared by tests of several stages.
# and the builders of small recordings and files (tests/python/builders.py).
sys.path.insert(0, str(ROOT / "tests" / "python" / "reference"))
sys.path.insert(0, str(ROOT / "tests" / "python"))
from shared_data import DATASETS  # noqa: E402 (after the path is set)


def _require_datasets() -> Path:
    manifest = DATASETS / "manifest.json"
    if not manifest.is_file():
        reason = f"real recordings not found: {manifest} is absent (set YOYOGAIT_DATASETS)"
        if os.environ.get("CI"):
            pytest.fail(reason + "; CI must have them")
        pytest.skip(reason)
    return DATASETS


@pytest.fixture(scope="session")
def datasets_dir() -> Path:
    """Folder of the real recordings; skips visibly without it, fails under CI."""
    return _require_datasets()


@pytest.fixture(scope="session")
def formats_dir(datasets_dir) -> Path:
    """Folder of real export samples (Nexus CSV, Motive CSV, MVNX, .mot, comma TRC); skips visibly, fails under CI."""
    folder = datasets_dir / "formats"
    if not (folder / "README.md").is_file():
        reason = f"real export samples not found: {folder} is absent"
        if os.environ.get("CI"):
            pytest.fail(reason + "; CI must have them")
        pytest.skip(reason)
    return folder


@pytest.fixture(scope="session")
def manifest(datasets_dir) -> dict:
    """The parsed manifest.json of the real recordings."""
    return json.loads((datasets_dir / "manifest.json").read_text())


@pytest.fixture(scope="session", autouse=True)
def lsl_machine_only(tmp_path_factory):
    """Lab Streaming Layer confined to this machine (127.0.0.1) and to this test run (its own SessionID).

    Set before pylsl is first used, for this process and the subprocesses the tests start.
    """
    import uuid

    cfg = tmp_path_factory.mktemp("lsl") / "lsl_api.cfg"
    cfg.write_text(
        "[ports]\nIPv6 = disable\n"
        "[multicast]\nResolveScope = machine\nListenAddress = 127.0.0.1\nAddressesOverride = {127.0.0.1}\n"
        f"[lab]\nKnownPeers = {{127.0.0.1}}\nSessionID = yoyogait-test-{uuid.uuid4().hex}\n"
        "[log]\nlevel = -3\n"
    )
    previous = os.environ.get("LSLAPICFG")
    os.environ["LSLAPICFG"] = str(cfg)
    yield cfg
    if previous is None:
        os.environ.pop("LSLAPICFG", None)
    else:
        os.environ["LSLAPICFG"] = previous


@pytest.fixture(scope="session", autouse=True)
def ros_machine_only():
    """ROS 2 discovery confined to this machine (LOCALHOST) and to this test run (a private ROS_DOMAIN_ID in
    100-200), set before rclpy is first initialised, for this process and the subprocesses the tests start."""
    import random

    names = ("ROS_AUTOMATIC_DISCOVERY_RANGE", "ROS_LOCALHOST_ONLY", "ROS_DOMAIN_ID", "ROS_STATIC_PEERS")
    previous = {n: os.environ.get(n) for n in names}
    os.environ["ROS_AUTOMATIC_DISCOVERY_RANGE"] = "LOCALHOST"
    os.environ.pop("ROS_LOCALHOST_ONLY", None)  # deprecated since Jazzy; the range above replaces it
    os.environ.pop("ROS_STATIC_PEERS", None)
    # Under pytest-xdist each worker draws from its own share of 100-200: two workers' nodes never meet.
    worker = os.environ.get("PYTEST_XDIST_WORKER", "gw0").removeprefix("gw")
    workers = int(os.environ.get("PYTEST_XDIST_WORKER_COUNT", "1"))
    span = max(1, 101 // max(1, workers))
    low = 100 + (int(worker) if worker.isdigit() else 0) * span % 101
    os.environ["ROS_DOMAIN_ID"] = str(random.SystemRandom().randint(low, min(200, low + span - 1)))
    yield int(os.environ["ROS_DOMAIN_ID"])
    for n, v in previous.items():
        if v is None:
            os.environ.pop(n, None)
        else:
            os.environ[n] = v
