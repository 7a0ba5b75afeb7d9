"""Figures are made, saved, hold the plotted data and say when data are synthetic."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
from matplotlib.figure import Figure

from yoyogait import synthetic as sy
from yoyogait.errors import InputError
from yoyogait.evaluation import figures as plots


@pytest.fixture(scope="module")
def walk():
    return sy.make_walk(sy.SUBJECTS[0], "3-rectangle")


@pytest.fixture(scope="module")
def fake_result(walk):
    """An estimator-like result on a 25 Hz grid (truth plus offsets, so lines differ)."""
    t = np.arange(0.0, walk.truth.time_s[-1], 0.04)
    tr = walk.truth.at(t)
    omega = 2 * np.pi * tr.step_frequency_hz
    state = np.column_stack([0.2 * np.cos(tr.theta_rad), 0.2 * np.sin(tr.theta_rad), omega * 0.04, tr.speed_mps])
    return (
        t,
        tr,
        SimpleNamespace(
            state=state,
            vx_hat_mps=tr.vx_path_mps + 0.05,
            vz_hat_mps=tr.vz_mps - 0.02,
            R_m=tr.R_m * 1.05,
            r_m=tr.r_m * 0.9,
            step_frequency_hz=-tr.step_frequency_hz,
            omega_rad_s=-omega,
            A0_mps=tr.speed_mps,
            A1_mps=tr.r_m * omega,
            speed_mps=tr.speed_mps,
        ),
    )


def suptitle(fig):
    return fig.get_suptitle() if hasattr(fig, "get_suptitle") else fig._suptitle.get_text()


def lines_by_label(fig):
    return {line.get_label(): line for ax in fig.axes for line in ax.get_lines()}


def test_parameter_figure_plots_fig3_panels(walk, fake_result, tmp_path):
    """Fig. 3: signed f (0 marked) vs DFT average and truth, R and r estimated and true, A0 and A1; PNG saved."""
    t, tr, result = fake_result
    out = tmp_path / "figs" / "params.png"
    fig = plots.parameter_figure(
        t, result, measured_vz_mps=tr.vz_mps, truth=walk.truth, title="walk 3, subject 1", path=out
    )
    assert isinstance(fig, Figure) and len(fig.axes) == 3
    assert out.is_file() and out.stat().st_size > 10_000
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    lines = lines_by_label(fig)
    np.testing.assert_allclose(lines["estimate f (signed)"].get_ydata(), result.step_frequency_hz)  # < 0 here
    np.testing.assert_allclose(lines["truth"].get_xdata(), walk.truth.time_s)
    np.testing.assert_allclose(lines["R est."].get_ydata(), result.R_m)
    np.testing.assert_allclose(lines["r true"].get_ydata(), walk.truth.r_m)
    np.testing.assert_allclose(lines["A1 (amplitude)"].get_ydata(), result.A1_mps)
    dft = [label for label in lines if label.startswith("DFT average")]
    assert len(dft) == 1
    f_dft = lines[dft[0]].get_ydata()[0]
    assert f_dft == pytest.approx(np.mean(tr.step_frequency_hz[tr.walking]), abs=0.05)
    assert "synthetic" in suptitle(fig).lower()


def test_parameter_figure_from_state_and_explicit_arrays():
    """Without A0/A1 fields the panels come from the EKF state; explicit arrays replace result fields."""
    t = np.linspace(0, 10, 251)
    state = np.column_stack([0.3 * np.cos(t), 0.4 * np.sin(t), np.full(t.size, 0.4), np.full(t.size, 1.2)])
    fig = plots.parameter_figure(
        t,
        SimpleNamespace(state=state, R_m=np.full(t.size, 0.3)),
        step_frequency_hz=np.full(t.size, 1.7),
        R_m=np.full(t.size, 0.12),
        dft_step_frequency_hz=1.75,
        title="real walk",
    )
    lines = lines_by_label(fig)
    np.testing.assert_allclose(lines["A0 (bias)"].get_ydata(), 1.2)
    np.testing.assert_allclose(lines["A1 (amplitude)"].get_ydata(), np.hypot(0.3 * np.cos(t), 0.4 * np.sin(t)))
    np.testing.assert_allclose(lines["R est."].get_ydata(), 0.12)
    assert lines["DFT average (1.75 Hz)"].get_ydata()[0] == 1.75
    assert "synthetic" not in suptitle(fig).lower()


def test_velocity_figure_plots_measured_and_reconstructed(walk, fake_result, tmp_path):
    """Fig. 4: measured and reconstructed v_x (top) and v_z (bottom) over time; PNG saved."""
    t, tr, result = fake_result
    out = tmp_path / "velocity.png"
    fig = plots.velocity_figure(
        t, tr.vx_path_mps, tr.vz_mps, result, title=plots.recording_title(walk.recording, "velocities"), path=out
    )
    assert out.is_file() and out.stat().st_size > 10_000
    top, bottom = fig.axes
    (mx, rx), (mz, rz) = top.get_lines(), bottom.get_lines()
    np.testing.assert_allclose(mx.get_ydata(), tr.vx_path_mps)
    np.testing.assert_allclose(rx.get_ydata(), result.vx_hat_mps)
    np.testing.assert_allclose(mz.get_ydata(), tr.vz_mps)
    np.testing.assert_allclose(rz.get_ydata(), result.vz_hat_mps)
    np.testing.assert_allclose(rz.get_xdata(), t)
    assert "synthetic" in suptitle(fig).lower()


def test_synthetic_flag_forces_the_word_into_the_title():
    """A synthetic figure says so even when the given title does not."""
    t = np.arange(5.0)
    fig = plots.velocity_figure(t, t, t, vx_hat_mps=t, vz_hat_mps=t, title="walk 1", synthetic=True)
    assert suptitle(fig).lower().startswith("synthetic")
    assert "walk 1" in suptitle(fig)


def test_recording_title_names_real_and_synthetic_sources(walk):
    """Titles from a recording say synthetic for synthetic walks and give the file for real ones."""
    assert "synthetic" in plots.recording_title(walk.recording).lower()
    real = SimpleNamespace(source="c3d_org_samples/MAC_Walk1.c3d", metadata={})
    assert plots.recording_title(real, "Fig. 3") == "Fig. 3 - c3d_org_samples/MAC_Walk1.c3d"


def test_arrays_of_the_wrong_length_are_refused():
    """An estimate not on the time grid is an input error, not a misleading figure."""
    with pytest.raises(InputError, match="vx_hat_mps"):
        plots.velocity_figure(np.arange(5.0), np.zeros(5), np.zeros(5), vx_hat_mps=np.zeros(4))


def _texts(fig):
    return [t.get_text() for t in fig.texts]


def test_synthetic_figures_carry_a_visible_mark(walk, fake_result):
    """Every synthetic figure has the boxed SYNTHETIC DATA label and the watermark; real ones have neither."""
    t, tr, result = fake_result
    figs = [
        plots.parameter_figure(t, result, truth=walk.truth),
        plots.velocity_figure(t, tr.vx_path_mps, tr.vz_mps, result, synthetic=True),
    ]
    for fig in figs:
        assert "SYNTHETIC DATA" in _texts(fig) and "SYNTHETIC" in _texts(fig)
    real = plots.velocity_figure(t, tr.vx_path_mps, tr.vz_mps, result)
    assert not any("SYNTHETIC" in text for text in _texts(real))


@pytest.fixture(scope="module")
def estimate_inputs():
    """A stop-and-go walk through the pipeline and the default estimator."""
    from yoyogait import GaitEstimator, gait_velocities

    w = sy.make_walk(sy.SUBJECTS[0], "5-stop-and-go", duration_s=25.0)
    vel = gait_velocities(w.recording)
    return w, vel, GaitEstimator().run(vel.vx, vel.vz, time_s=vel.time_s)


def test_estimate_figure_has_bands_standing_cadence_and_a_zoom(estimate_inputs, tmp_path):
    """The estimate figure: velocities with reconstruction, +-2 sigma bands on f and speed, standing
    shaded, the foot-contact cadence, 0 Hz marked, and a 5 s zoom inside the walking part."""
    w, vel, res = estimate_inputs
    cadence = np.full(vel.time_s.shape, 1.8)
    out = tmp_path / "estimate.png"
    fig = plots.estimate_figure(
        vel, res, reference_step_frequency_hz=cadence, contacts_s=[10.0, 10.55, 11.1], synthetic=True, path=out
    )
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    ax_x, ax_z, ax_f, ax_s, zoom_x, zoom_z = fig.axes
    labels = {ax: [h for h in ax.get_legend_handles_labels()[1]] for ax in fig.axes}
    assert "reconstructed $v_x$" in labels[ax_x] and "standing" in labels[ax_x]
    assert "±2σ" in labels[ax_f] and "±2σ" in labels[ax_s] and "cadence (foot contacts)" in labels[ax_f]
    lines = {line.get_label(): line for line in ax_f.get_lines()}
    drawn = np.asarray(lines["estimate (signed)"].get_ydata())
    np.testing.assert_allclose(drawn[vel.walking], res.step_frequency_hz[vel.walking])
    held = np.asarray(lines["held while standing"].get_ydata())  # standing: grey and dashed, as held
    np.testing.assert_allclose(held[~vel.walking], res.step_frequency_hz[~vel.walking])
    assert lines["held while standing"].get_linestyle() == "--"
    assert any(np.all(np.asarray(line.get_ydata()) == 0) for line in ax_f.get_lines())  # 0 Hz marked
    lo, hi = zoom_z.get_xlim()
    assert hi - lo == pytest.approx(5.0)
    walking = vel.walking[(vel.time_s >= lo) & (vel.time_s <= hi)]
    assert walking.all()
    assert "foot contact" in labels[zoom_z] or not (lo <= 10.0 <= hi)
    assert "SYNTHETIC DATA" in _texts(fig)


def _pixels(fig):
    fig.canvas.draw()
    return np.asarray(fig.canvas.buffer_rgba()).copy()


def test_a_figure_drawn_into_an_earlier_one_is_the_same_as_a_new_one(walk, fake_result):
    """Drawn into one that held another recording (synthetic, longer, other lines), a figure has a new one's pixels."""
    t, tr, result = fake_result
    n = t.size // 3
    short = SimpleNamespace(**{k: v[:n] for k, v in vars(result).items()})
    cases = [
        (
            plots.parameter_figure(t, result, truth=walk.truth, title="synthetic walk"),
            lambda into=None: plots.parameter_figure(
                t[:n], short, dft_step_frequency_hz=1.72, reference_step_frequency_hz=np.full(n, 1.7), into=into
            ),
        ),
        (
            plots.velocity_figure(t, tr.vx_path_mps, tr.vz_mps, result, synthetic=True),
            lambda into=None: plots.velocity_figure(t[:n], tr.vx_path_mps[:n], tr.vz_mps[:n], short, into=into),
        ),
    ]
    for first, draw in cases:
        _pixels(first)
        again = draw(into=first)
        assert again is first and not any("SYNTHETIC" in text for text in _texts(again))
        np.testing.assert_array_equal(_pixels(again), _pixels(draw()))


def _all_texts(fig):
    return [t.get_text() for t in fig.texts] + [t.get_text() for ax in fig.axes for t in ax.texts]


def _short_real_walk(seconds=3.7):
    """A short real-like walk (not marked synthetic) through the pipeline and the default estimator."""
    from builders import stepping_walk
    from yoyogait import GaitEstimator, gait_velocities

    rec, contacts = stepping_walk(stand_before_s=0.5, walk_s=seconds - 1.0, stand_after_s=0.5)
    vel = gait_velocities(rec)
    return vel, GaitEstimator().run(vel.vx, vel.vz, time_s=vel.time_s), contacts[contacts > 0]


def test_the_zoom_stays_inside_a_short_recording():
    """On a 3.7 s recording the 5 s zoom shows the recording, never time past its end."""
    vel, res, contacts = _short_real_walk(3.7)
    fig = plots.estimate_figure(vel, res, contacts_s=contacts)
    lo, hi = fig.axes[-1].get_xlim()
    assert vel.time_s[0] <= lo and hi <= vel.time_s[-1] + 1e-9


def test_a_missing_or_untrusted_reference_says_so():
    """No reference: a note in the step frequency panel; an untrusted one: dotted, labelled and its reason given."""
    from yoyogait.pipeline.events import ReferenceQuality

    vel, res, _ = _short_real_walk(6.0)
    fig = plots.parameter_figure(vel.time_s, res, walking=vel.walking, title="walk")
    assert any(t.startswith("no reference step frequency") for t in _all_texts(fig))
    bad = ReferenceQuality("foot contacts", 3, 1.5, float("nan"), 1.8, 0.3, 0, False, "3 steps, fewer than 4")
    fig = plots.parameter_figure(
        vel.time_s, res, reference_step_frequency_hz=np.full(vel.time_s.shape, 1.5), reference_quality=bad
    )
    line = lines_by_label(fig)["reference (foot contacts), not trusted"]
    assert line.get_linestyle() == ":"
    assert "reference not trusted: 3 steps, fewer than 4" in _all_texts(fig)


def test_evaluate_figures_shade_standing_and_carry_bands():
    """The parameter and velocity figures shade standing, draw the held estimate dashed and have +-2 sigma bands."""
    vel, res, _ = _short_real_walk(6.0)
    for fig in (
        plots.parameter_figure(vel.time_s, res, walking=vel.walking),
        plots.velocity_figure(vel.time_s, vel.vx, vel.vz, res, walking=vel.walking),
    ):
        labels = [label for ax in fig.axes for label in ax.get_legend_handles_labels()[1]]
        assert "standing" in labels and "held while standing" in labels
        assert any(label.startswith("±2σ") for label in labels)


def test_titles_name_the_conditions_and_come_from_the_api():
    """Treadmill and markerless are named in the title; without a title the figure is named after the file."""
    vel, res, _ = _short_real_walk(6.0)
    fig = plots.estimate_figure(vel, res, conditions=("treadmill", "markerless"))
    assert suptitle(fig).endswith("(treadmill, markerless)") and suptitle(fig).startswith("synthetic: pelvis")
    rec = SimpleNamespace(metadata={}, point_names=["r.ASIS_study", "L.ASIS_study"])
    treadmill = SimpleNamespace(treadmill=SimpleNamespace(detected=True))
    assert plots.recording_conditions(rec, treadmill) == ("treadmill", "markerless")
    fig = plots.velocity_figure(vel.time_s, vel.vx, vel.vz, res, conditions=("treadmill",), title="walk 3")
    assert suptitle(fig) == "walk 3 (treadmill)"
