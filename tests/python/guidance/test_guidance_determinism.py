"""The same seed gives the same walk and the same table, bit for bit; another seed another walk."""

from __future__ import annotations

import numpy as np

from yoyogait.guidance import simulate
from yoyogait.guidance.study import run_study, runs_csv, table_csv
from yoyogait.synthetic import SUBJECTS


def test_the_same_seed_gives_the_same_table_bit_for_bit(short_path):
    """Two studies with the same seed write identical table and per-walk CSV bytes."""
    a = run_study([short_path], SUBJECTS[:2], ("raw", "yoyogait-predicted"), seed=7)
    b = run_study([short_path], SUBJECTS[:2], ("raw", "yoyogait-predicted"), seed=7)
    assert table_csv(a) == table_csv(b) and runs_csv(a) == runs_csv(b)


def test_another_seed_gives_another_walk(short_path):
    """A different seed changes the motion-capture noise and the gait phase, hence the force."""
    a = simulate(short_path, SUBJECTS[0], "raw", seed=1)
    b = simulate(short_path, SUBJECTS[0], "raw", seed=2)
    n = min(len(a.time_s), len(b.time_s))
    assert not np.array_equal(a.force_n[:n], b.force_n[:n])


def test_the_sources_see_the_same_walk(short_path):
    """For one seed the motion-capture noise and the walk before the guidance starts are the same for every source."""
    a = simulate(short_path, SUBJECTS[0], "none", seed=3)
    b = simulate(short_path, SUBJECTS[0], "yoyogait", seed=3)
    noise_a = a.handle_measured_m - a.hand_m
    noise_b = b.handle_measured_m - b.hand_m
    n = min(len(a.time_s), len(b.time_s))
    assert np.allclose(noise_a[:n], noise_b[:n], rtol=0.0, atol=1e-12)
    before = a.time_s[:n] < a.config.start_s
    assert np.array_equal(a.hand_m[:n][before], b.hand_m[:n][before])
