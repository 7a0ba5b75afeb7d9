"""The reference on the shared manifest: every recording it trusts agrees with the DFT of its vertical
velocity, and the default estimator's step frequency error against the trusted references meets its target."""

from __future__ import annotations

import numpy as np
import pytest

from yoyogait import evaluation as ev
from yoyogait.pipeline import spectral

#: The targets: the trusted reference's cadence within this of the DFT of the vertical velocity ...
DFT_AGREEMENT_HZ = 0.05
#: ... and the default's median step-frequency error against the trusted references at most this.
DEFAULT_F_ERR_HZ = 0.0213


@pytest.fixture(scope="module")
def evaluation(datasets_dir):
    items, missing = ev.manifest_items(datasets_dir / "manifest.json")
    assert not missing, missing
    return ev.evaluate(items, ("default",))


def test_trusted_references_agree_with_the_vertical_velocity(evaluation):
    """On every recording whose reference is trusted, its cadence is within 0.05 Hz of the DFT of the vertical
    velocity over its longest walking stretch (computed here again), and most recordings are trusted."""
    trusted = [r for r in evaluation.items if r.reference_quality.trusted]
    assert len(trusted) >= len(evaluation.items) // 2
    for r in trusted:
        q = r.reference_quality
        vel = r.velocities
        segments = [(a, b) for a, b in _runs(vel.time_s, r.walking) if b - a >= 1.0]
        a, b = max(segments, key=lambda s: s[1] - s[0])
        span = (vel.time_s >= a) & (vel.time_s <= b) & np.isfinite(vel.vz)
        dft = spectral.step_frequency(vel.vz[span], vel.rate_hz, min_hz=0.3, max_hz=4.0)
        assert abs(q.cadence_hz - dft) <= DFT_AGREEMENT_HZ, (r.item.name, q.summary(), dft)


def test_default_step_frequency_error_against_trusted_references(evaluation):
    """The default's median step-frequency error over the recordings with a trusted reference is <= 0.0213 Hz."""
    errors = [r.metrics["default"]["f_err_median_hz"] for r in evaluation.items if r.reference_quality.trusted]
    errors = np.array(errors, dtype=float)
    assert np.isfinite(errors).sum() >= 10
    assert np.nanmedian(errors) <= DEFAULT_F_ERR_HZ


def test_untrusted_references_are_flagged_and_counted(evaluation):
    """Each untrusted reference says why in recordings.csv's columns, and the summary counts and names them."""
    rows = [row for row in evaluation.rows() if row["estimator"] == "default"]
    left = [row for row in rows if not row["reference_trusted"]]
    assert left and all(row["reference_reason"] for row in left)
    text = ev.summary_markdown(evaluation)
    n_trusted = len(rows) - len(left)
    assert f"References trusted on {n_trusted} of {len(rows)} recordings" in text
    assert f"{n_trusted} trusted reference" in text


def _runs(t, mask):
    """(start, end) times of the runs of True in mask."""
    m = np.concatenate([[False], np.asarray(mask, dtype=bool), [False]])
    edges = np.flatnonzero(np.diff(m.astype(np.int8)))
    return [(float(t[a]), float(t[b - 1])) for a, b in zip(edges[::2], edges[1::2])]


def test_online_evaluation_trusts_the_references_the_offline_one_trusts(datasets_dir, evaluation):
    """evaluate --online judges each real recording's reference as evaluate does (honesty is
    measured against the trusted references), and its summary repeats the reference rows over them."""
    by_name = {r.item.name: r.reference_quality.trusted for r in evaluation.items}
    items, _ = ev.manifest_items(datasets_dir / "manifest.json")
    chosen = [i for i in items if i.name in {"sample23_Vicon_analysis.c3d", "Vicon_pyCGM2_CGM24_Walking01.c3d"}]
    assert len(chosen) == 2
    online = ev.evaluate_online(chosen)
    assert {r.item.name: r.reference_quality.trusted for r in online.items} == {i.name: by_name[i.name] for i in chosen}
    assert sorted(by_name[i.name] for i in chosen) == [False, True]
    table = online.summary_table()
    assert "confidently wrong, share of walking, 1 trusted references" in table
    assert "not trusted: `sample23_Vicon_analysis.c3d`" in table
