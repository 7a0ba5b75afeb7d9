"""Corrupt-file run: hundreds of mutants of real recordings through ``inspect`` and ``estimate``.

    python bench/corrupt.py                      # 415 mutants (or $YOYOGAIT_MUTANTS), seed 0
    python bench/corrupt.py --mutants 1000 --seed 3 --show 20

Prints how many runs ended in a traceback, left a partial output, gave a message that is not one
line naming the file, or accepted an absurd result (median speed >= 3 m/s, step frequency outside
0.5-3.5 Hz), per format and mutation, and lists the first of them.  The mutants are those of
tests/python/reference/corrupt_mutants.py (the test runs the first few dozen).  Exit status 1 if any run is
not ok.
"""

from __future__ import annotations

import argparse
import collections
import os
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests" / "python" / "reference"))

import corrupt_mutants as cm  # noqa: E402 (after the path is set)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--mutants", type=int, default=int(os.environ.get("YOYOGAIT_MUTANTS", 415)))
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--start", type=int, default=0, help="first mutant index")
    parser.add_argument("--figure-every", type=int, default=1, help="draw the estimate figure every N-th mutant")
    parser.add_argument(
        "--datasets",
        type=Path,
        default=Path(os.environ.get("YOYOGAIT_DATASETS", ROOT.parent / "shared" / "datasets")),
    )
    parser.add_argument("--show", type=int, default=10, help="list this many runs that are not ok")
    args = parser.parse_args()
    if not (args.datasets / "manifest.json").is_file():
        print(f"real recordings not found in {args.datasets} (set YOYOGAIT_DATASETS)", file=sys.stderr)
        return 2

    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="yoyogait-corrupt-") as work:
        tally = cm.run_mutants(
            args.datasets, Path(work), args.mutants, seed=args.seed, figure_every=args.figure_every, start=args.start
        )
    seconds = time.perf_counter() - t0

    runs = len(tally.outcomes)
    print(f"{args.mutants} mutants (seed {args.seed}), {runs} runs (inspect + estimate), {seconds:.0f} s")
    print()
    print("| outcome | runs |")
    print("|---|---|")
    for category in cm.CATEGORIES:
        print(f"| {category} | {tally.count(category)} |")
    errors = sum(o.code not in (0, None) and o.category == "ok" for o in tally.outcomes)
    print(f"| (of ok: one-line errors / plausible results) | {errors} / {tally.count('ok') - errors} |")

    by = collections.Counter()
    for o in tally.outcomes:
        kind = "error" if o.code and o.category == "ok" else o.category
        by[(Path(o.mutant.source).suffix[1:], o.mutant.operator, kind)] += 1
    print()
    print("| format | mutation | one-line error | plausible result | not ok |")
    print("|---|---|---|---|---|")
    for fmt, op in sorted({(f, op) for f, op, _ in by}):
        ok_error = by[(fmt, op, "error")]
        plausible = by[(fmt, op, "ok")]
        bad = sum(n for (f, o, c), n in by.items() if f == fmt and o == op and c not in ("error", "ok"))
        print(f"| {fmt} | {op} | {ok_error} | {plausible} | {bad} |")

    bad = tally.bad()
    if bad:
        print()
        for o in bad[: args.show]:
            m = o.mutant
            print(f"- [{o.category}] {o.command} mutant {m.index} ({m.source}, {m.operator}: {m.detail}): {o.message}")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
