"""The feet's steps online (docs/online.md, "Feet"): the shared recordings re-rendered as a markerless capture."""

from __future__ import annotations

import dataclasses
import functools

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from builders import write_trc
from yoyogait import synthetic as sy
from yoyogait import synthetic_conditions as sc
from yoyogait.cli import main
from yoyogait.estimators import OnlineConfig, OnlineEstimator
from yoyogait.evaluation.datasets import manifest_items
from yoyogait.evaluation.online import evaluate_item_online
from yoyogait.evaluation.tables import trusted


def _markerless(load):
    return sc.markerless_noise(load(), seed=0, rate_hz=60.0)


def test_markerless_re_renderings_with_heels_are_never_confidently_wrong_on_a_trusted_reference(datasets_dir):
    """The shared recordings with feet and a trusted reference, re-rendered markerless (2 cm, swaps, dropouts, 60 Hz):
    with the heels confidently wrong on at most 1 % of the walking of each, valid on more than half of it after 3 s
    (median over them) and on at least the target's 80 % of it on four in five of them; without the heels, never
    valid (median)."""
    items, _ = manifest_items(datasets_dir / "manifest.json")
    wrong, valid, valid_without = [], [], []
    for item in items:
        if not item.feet:
            continue
        clean = evaluate_item_online(item)
        if not trusted(clean):
            continue
        noisy = dataclasses.replace(item, load=functools.partial(_markerless, item.load))
        with_feet = evaluate_item_online(noisy, reference=item, feet=True).metrics["online"]
        without = evaluate_item_online(noisy, reference=item).metrics["online"]
        wrong.append((with_feet["confidently_wrong_fraction"], item.name))
        if not np.isnan(with_feet["valid_after3s_fraction"]):
            valid.append(with_feet["valid_after3s_fraction"])
            valid_without.append(without["valid_after3s_fraction"])
    assert len(wrong) >= 20
    worst = max(wrong)
    assert worst[0] <= 0.01, worst
    assert np.median(valid) > 0.5 and np.median(valid_without) == 0.0
    assert np.mean(np.asarray(valid) >= 0.8) >= 0.8, sorted(valid)


def test_estimate_online_says_to_give_the_feet_and_is_valid_with_them(tmp_path, capsys):
    """estimate --online on a SYNTHETIC markerless walk: without --feet a line names the heels to give; with them
    the CSV is valid on most of the walking after 5 s."""
    walk = sc.render("markerless-60hz", sy.SUBJECTS[0])
    path = write_trc(tmp_path / "markerless.trc", walk.recording)
    out = tmp_path / "o.csv"
    assert main(["estimate", str(path), "--online", "--out", str(out)]) == 0
    assert "give --feet LHEE,RHEE (heels or ankles)" in capsys.readouterr().out
    assert main(["estimate", str(path), "--online", "--feet", "LHEE,RHEE", "--out", str(out), "--force"]) == 0
    assert "give --feet" not in capsys.readouterr().out
    table = np.genfromtxt(out, delimiter=",", names=True)
    late = table["time_s"] >= 5.0
    assert table["valid"][late].mean() > 0.5


def test_evaluate_online_feet_puts_the_feet_into_the_frames(tmp_path, capsys):
    """evaluate --online --online-feet on a SYNTHETIC markerless walk: valid on most of the walking (about never
    without the flag); --online-feet without --online: exit 2, one line naming it."""
    data = tmp_path / "walks"
    data.mkdir()
    write_trc(data / "markerless.trc", sc.render("markerless-60hz", sy.SUBJECTS[0]).recording)
    shares = []
    for extra in ([], ["--online-feet"]):
        out = tmp_path / f"report{len(extra)}"
        assert main(["evaluate", str(data), "--online", *extra, "--out", str(out), "--no-figures", "--jobs", "1"]) == 0
        rows = np.genfromtxt(out / "recordings.csv", delimiter=",", names=True, dtype=None, encoding="utf-8")
        shares.append(float(rows["valid_fraction"][rows["estimator"] == "online"][0]))
    assert shares[0] < 0.2 < 0.5 < shares[1], shares
    capsys.readouterr()
    assert main(["evaluate", str(data), "--online-feet", "--out", str(tmp_path / "r"), "--no-figures"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--online-feet" in err[0]


def test_another_walkers_feet_beside_the_pelvis_make_nothing_valid():
    """SYNTHETIC markerless walk of subject 1 (1.80 steps/s) with the heels of subject 3's (1.99 steps/s) 1 m beside
    it in the frames: they are not taken (no feet's figure), so it is as valid as without feet and never confidently
    wrong."""
    own = sc.render("markerless-60hz", sy.SUBJECTS[0])
    other = sc.render("markerless-60hz", sy.SUBJECTS[2]).recording
    pelvis, heels = ["LASI", "RASI", "LPSI", "RPSI"], list(sy.HEEL_MARKERS)
    n = min(own.recording.n_frames, other.n_frames)
    t = np.asarray(own.recording.time_s[:n])
    feet = other.points(heels)[:n] + np.array([0.0, 1.0, 0.0])
    frames = np.concatenate([own.recording.points(pelvis)[:n], feet], axis=1)
    est = OnlineEstimator(pelvis, "z", feet=heels)
    r = est.run(t, frames)
    without = OnlineEstimator(pelvis, "z").run(t, frames[:, :4])
    tr = own.truth.at(t)
    err = np.abs(r.step_frequency_hz - tr.step_frequency_hz)
    assert est.feet_step_frequency_hz is None
    np.testing.assert_array_equal(r.valid, without.valid)
    assert not (r.valid & np.asarray(tr.walking, dtype=bool) & (err > 0.15) & (err > 2 * r.step_frequency_std_hz)).any()


@functools.cache
def _walk_with_heels(condition: str):
    """A SYNTHETIC walk (a lab walk, or a markerless rendering at 60 Hz) and its pelvis and heel frames."""
    subject = sy.SUBJECTS[1]
    walk = sy.make_walk(subject, "1-straight", seed=3) if condition == "lab" else sc.render(condition, subject)
    pelvis = list(sy.PELVIS_MARKERS)
    frames = walk.recording.points(pelvis + list(sy.HEEL_MARKERS))
    frames.setflags(write=False)
    return walk, pelvis, np.asarray(walk.recording.time_s), frames


def _broken_feet(kind: str, t, frames, rng):
    """The frames with their two feet broken as a tracker breaks them (the pelvis untouched)."""
    out = frames.copy()
    feet = out[:, -2:, :]
    n = len(t)
    if kind == "flicker":  # each foot missing on most frames
        feet[rng.random((n, 2)) < rng.uniform(0.2, 0.9)] = np.nan
    elif kind == "absurd":  # a few frames with a foot at 1e6 m, 1e300 m or inf
        feet[rng.random(n) < 0.02, int(rng.integers(0, 2)), int(rng.integers(0, 3))] = rng.choice([1e6, -1e300, np.inf])
    elif kind == "zeros":  # a tracker's lost point at the origin
        feet[rng.random(n) < 0.3] = 0.0
    elif kind == "jump":  # one foot's track jumps for good
        feet[int(rng.integers(0, n)) :, 0] += rng.normal(0.0, 2.0, 3)
    elif kind == "frozen":  # both feet stuck where they were first seen
        feet[:] = feet[0]
    elif kind == "same":  # both labels on one foot
        feet[:, 1] = feet[:, 0]
    elif kind == "swaps":  # left and right exchanged on a third of the frames
        swap = rng.random(n) < 0.3
        feet[swap] = feet[swap][:, ::-1]
    elif kind == "one":  # one foot never seen
        feet[:, 1] = np.nan
    elif kind == "far":  # both feet displaced by metres
        feet += np.array([rng.uniform(-5.0, 5.0), rng.uniform(-5.0, 5.0), 0.0])
    return out


@settings(max_examples=16, deadline=None)
@given(
    condition=st.sampled_from(["lab", "markerless-60hz"]),
    kind=st.sampled_from(["flicker", "absurd", "zeros", "jump", "frozen", "same", "swaps", "one", "far"]),
    seed=st.integers(0, 10**6),
)
def test_broken_feet_keep_outputs_finite_bounded_deterministic_and_never_confidently_wrong(condition, kind, seed):
    """Feet a tracker breaks (missing, absurd, at the origin, jumping, frozen, one point twice, swapped, far off) on
    SYNTHETIC walks: no exception, outputs finite and within max_plausible_speed_mps, stds never NaN, the same run
    twice, and valid estimates never confidently wrong."""
    walk, pelvis, t, frames = _walk_with_heels(condition)
    broken = _broken_feet(kind, t, frames, np.random.default_rng(seed))
    runs = [OnlineEstimator(pelvis, "z", feet=list(sy.HEEL_MARKERS)).run(t, broken) for _ in range(2)]
    r = runs[0]
    limit = OnlineConfig().max_plausible_speed_mps
    for name in ("vx_hat_mps", "vz_hat_mps", "speed_mps", "walk_a_mps", "walk_b_mps", "vx_mps", "vz_mps"):
        v = getattr(r, name)
        assert np.all(np.isfinite(v)) and np.all(np.abs(v) <= limit), name
        np.testing.assert_array_equal(v, getattr(runs[1], name))
    for name in ("step_frequency_std_hz", "speed_std_mps", "step_frequency_hz", "gait_phase"):
        assert not np.isnan(getattr(r, name)).any(), name
    np.testing.assert_array_equal(r.valid, runs[1].valid)
    truth = walk.truth.at(t)
    f_err = np.abs(r.step_frequency_hz - truth.step_frequency_hz)
    s_err = np.abs(r.speed_mps - truth.speed_mps)
    walking = np.asarray(truth.walking, dtype=bool)
    wrong = (r.valid & walking) & (
        ((f_err > 0.15) & (f_err > 2 * r.step_frequency_std_hz)) | ((s_err > 0.15) & (s_err > 2 * r.speed_std_mps))
    )
    assert wrong.sum() <= 0.01 * walking.sum(), (kind, wrong.sum())
