"""Corrupt copies of real recordings through ``inspect`` and ``estimate``: a one-line error naming the
file or a plausible result; never a traceback, a partial output or an absurd number.

The mutants (truncated files, flipped bytes, zeroed blocks, bad header numbers, bogus timestamps and
cells, deleted or repeated lines of C3D, TRC, BVH, a velocity CSV, a lower-back IMU's mobgap CSV and
Mobilise-D data.mat) are those of
corrupt_mutants.py, seeded.  The test runs the first 32; set ``YOYOGAIT_MUTANTS=415`` (or more) for
a long run, or use bench/corrupt.py, which prints the counts.
"""

from __future__ import annotations

import os

import corrupt_mutants as cm

N_MUTANTS = int(os.environ.get("YOYOGAIT_MUTANTS", 32))


def test_mutants_are_deterministic(datasets_dir, tmp_path):
    """The same seed and index give the same corrupt bytes; another seed gives other ones."""

    def mutant(folder: str, seed: int) -> bytes:
        (tmp_path / folder).mkdir()
        return cm.make_mutant(datasets_dir, tmp_path / folder, seed, 5).path.read_bytes()

    a, b, c = mutant("a", 0), mutant("b", 0), mutant("c", 1)
    original = (datasets_dir / cm.SOURCES[5]).read_bytes()
    assert a == b and a != original and c != a


def test_corrupt_recordings_give_one_line_errors_or_plausible_results(datasets_dir, tmp_path):
    """Every mutant ends, in inspect and in estimate, in one error line naming the file (and no output
    left) or in a plausible result (median speed < 3 m/s, step frequency 0.5-3.5 Hz)."""
    tally = cm.run_mutants(datasets_dir, tmp_path, N_MUTANTS, seed=0, figure_every=8)
    bad = tally.bad()
    assert not bad, "\n".join(
        f"[{o.category}] {o.command} mutant {o.mutant.index} ({o.mutant.source}, {o.mutant.detail}): {o.message}"
        for o in bad
    )
    # The mutants do break files: a good share of the runs end in an error, and every format is hit.
    errors = [o for o in tally.outcomes if o.code not in (0, None)]
    assert len(errors) >= len(tally.outcomes) // 4
    assert {cm.source_format(o.mutant.source) for o in errors} == {"c3d", "trc", "bvh", "csv", "imucsv", "mat"}
    assert not list((tmp_path / "out").iterdir())
