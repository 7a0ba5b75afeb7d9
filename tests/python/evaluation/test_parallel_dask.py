"""Evaluation on a Dask cluster (a local one on loopback): the same report as a serial run, with the
files read by the workers or shipped with the tasks; an unreachable scheduler is one error line."""

from __future__ import annotations

import json

import pytest

from yoyogait import evaluation as ev
from yoyogait.cli import main
from yoyogait.evaluation import parallel

distributed = pytest.importorskip("distributed", reason="Dask distributed is not installed (yoyogait[distributed])")

CHOSEN = ("c3d_org_samples/MAC_Walk1.c3d", "opensim_models/Rajagopal_motion_capture_walk.trc")


@pytest.fixture(scope="module")
def cluster():
    """A Dask cluster of one in-process worker with two threads, listening on 127.0.0.1 only."""
    with distributed.LocalCluster(
        n_workers=1,
        threads_per_worker=2,
        processes=False,
        protocol="tcp",
        host="127.0.0.1",
        dashboard_address=None,
    ) as c:
        yield c


@pytest.fixture(scope="module")
def two_recordings(manifest, datasets_dir, tmp_path_factory):
    chosen = [r for r in manifest["recordings"] if r["path"] in CHOSEN]
    folder = tmp_path_factory.mktemp("dask")
    doc = {"recordings": [{**r, "path": str((datasets_dir / r["path"]).resolve())} for r in chosen]}
    (folder / "manifest.json").write_text(json.dumps(doc))
    return folder / "manifest.json"


@pytest.mark.parametrize("ship", [False, True], ids=["paths", "shipped"])
def test_scheduler_gives_the_serial_report(cluster, two_recordings, tmp_path, ship):
    """`evaluate --scheduler` writes the per-recording CSV and tables of a serial run, byte for byte."""
    serial = tmp_path / "serial"
    args = [str(two_recordings), "--estimators", "paper,default", "--no-figures"]
    assert main(["evaluate", *args, "--out", str(serial), "--jobs", "1"]) == 0
    remote = tmp_path / "remote"
    extra = ["--ship-files"] if ship else []
    assert main(["evaluate", *args, "--out", str(remote), "--scheduler", cluster.scheduler_address, *extra]) == 0
    for name in ("recordings.csv", "table1_paper.csv", "table1_default.csv", "index.md"):
        assert (serial / name).read_bytes() == (remote / name).read_bytes(), name


def test_shipped_item_reads_without_the_file(two_recordings, tmp_path):
    """A shipped item carries its file's bytes: it loads after the file is gone."""
    items, _, _ = ev.resolve_dataset(str(two_recordings))
    copy = tmp_path / "walk.c3d"
    copy.write_bytes(ev.datasets.Path(items[0].load.args[0]).read_bytes())
    item = ev.shipped(
        ev.Item(name="walk.c3d", subject="s", walk="w", load=ev.datasets.functools.partial(ev.datasets.io.read, copy))
    )
    copy.unlink()
    assert item.load().positions_m.shape[0] > 100


def test_unreachable_scheduler_is_one_error_line(capsys):
    """No scheduler at the address: InputError naming it, within the timeout."""
    with pytest.raises(ev.datasets.InputError, match=r"cannot reach the Dask scheduler at tcp://127\.0\.0\.1:9"):
        with parallel.dask_executor("tcp://127.0.0.1:9", timeout_s=1.0):
            pass
