"""Tables of an evaluation: Table I of the paper per estimator, and the summary over recordings."""

from __future__ import annotations

import csv
import dataclasses
import io as _io
import math

import numpy as np

from .running import Evaluation

__all__ = [
    "table_one",
    "table_one_markdown",
    "table_one_csv",
    "summary_markdown",
    "median_and_worst",
    "median_and_worst_markdown",
    "SUMMARY_KEYS",
    "md_text",
    "md_code",
    "REFERENCE_KEYS",
    "reference_counts",
    "trusted",
]

_MD_PUNCT = set("\\`*[]<>|!&~#")


def _printable(text: str) -> str:
    """One line: line breaks and other control characters become spaces."""
    return "".join(" " if (ord(c) < 32 or 0x7F <= ord(c) < 0xA0 or c in "\u2028\u2029") else c for c in str(text))


def md_text(text) -> str:
    """``text`` (a name from a file, a folder or a manifest) as Markdown that renders as that text: every
    character that could start a link, an image, HTML, emphasis, code or a table cell is escaped, on one
    line; an underscore inside a word (``sample_10``) is left as it is (it cannot start emphasis)."""
    t = _printable(text)
    out = []
    for k, c in enumerate(t):
        if c in _MD_PUNCT:
            out.append("\\" + c)
        elif c == "_" and not (0 < k < len(t) - 1 and t[k - 1].isalnum() and t[k + 1].isalnum()):
            out.append("\\_")
        else:
            out.append(c)
    return "".join(out)


def md_code(text) -> str:
    """``text`` as a Markdown code span that shows it verbatim, whatever backticks it holds (the fence is
    longer than any run of backticks inside), on one line."""
    t = _printable(text)
    longest = max((len(run) for run in _runs(t)), default=0)
    fence = "`" * (longest + 1)
    pad = " " if t.startswith("`") or t.endswith("`") or (t.startswith(" ") and t.endswith(" ") and t.strip()) else ""
    return f"{fence}{pad}{t}{pad}{fence}"


def _runs(text: str) -> list[str]:
    runs, current = [], ""
    for c in text:
        if c == "`":
            current += c
        elif current:
            runs.append(current)
            current = ""
    if current:
        runs.append(current)
    return runs


def _pool(stats) -> tuple[float, float]:
    """Mean and standard deviation of the union of groups given as (n, mean, std)."""
    stats = [(n, m, s) for n, m, s in stats if n and n > 0 and math.isfinite(m) and math.isfinite(s)]
    if not stats:
        return float("nan"), float("nan")
    total = sum(n for n, _, _ in stats)
    mean = sum(n * m for n, m, _ in stats) / total
    second = sum(n * (s * s + m * m) for n, m, s in stats) / total
    return mean, math.sqrt(max(second - mean * mean, 0.0))


def table_one(evaluation: Evaluation, estimator: str):
    """Table I: rows (walk type, component), columns subjects; cells (mean, std) in 1e-2 (m/s)^2.

    A cell with several recordings pools their samples.
    """
    subjects = sorted({r.item.subject for r in evaluation.items})
    walks = sorted({r.item.walk for r in evaluation.items})
    rows = []
    for walk in walks:
        for comp in ("vx", "vz"):
            cells = []
            for subj in subjects:
                group = [
                    r.metrics[estimator] for r in evaluation.items if r.item.walk == walk and r.item.subject == subj
                ]
                cells.append(
                    _pool(
                        [(m["samples_n"], m[f"{comp}_sq_err_mean_1e-2"], m[f"{comp}_sq_err_std_1e-2"]) for m in group]
                    )
                    if group
                    else None
                )
            rows.append((walk, comp, cells))
    return subjects, rows


def _cell(c) -> str:
    if c is None:
        return ""
    mean, std = c
    if not math.isfinite(mean):
        return "n/a"
    return f"{_num(mean)} (±{_num(std)})"


def _num(v: float) -> str:
    if v >= 100:
        return f"{v:.0f}"
    if v >= 10:
        return f"{v:.1f}"
    return f"{v:.2f}" if v >= 0.1 else f"{v:.3f}"


def table_one_markdown(evaluation: Evaluation, estimator: str) -> str:
    subjects, rows = table_one(evaluation, estimator)
    head = "| walk type & component | " + " | ".join(md_text(s) for s in subjects) + " |"
    lines = [head, "|---|" + "---:|" * len(subjects)]
    for walk, comp, cells in rows:
        label = f"{md_text(walk)}: v_x error" if comp == "vx" else "  v_z error"
        lines.append(f"| {label} | " + " | ".join(_cell(c) for c in cells) + " |")
    return "\n".join(lines)


def table_one_csv(evaluation: Evaluation, estimator: str) -> str:
    subjects, rows = table_one(evaluation, estimator)
    buf = _io.StringIO()
    w = csv.writer(buf)
    w.writerow(["walk", "component"] + [f"{s} mean_1e-2" for s in subjects] + [f"{s} std_1e-2" for s in subjects])
    for walk, comp, cells in rows:
        w.writerow(
            [walk, comp]
            + [("" if c is None else f"{c[0]:.6g}") for c in cells]
            + [("" if c is None else f"{c[1]:.6g}") for c in cells]
        )
    return buf.getvalue()


SUMMARY_KEYS = (
    ("vx_sq_err_mean_1e-2", "v_x sq. error (1e-2 (m/s)^2)"),
    ("vz_sq_err_mean_1e-2", "v_z sq. error (1e-2 (m/s)^2)"),
    ("f_err_median_hz", "step freq. error median (Hz)"),
    ("f_wrong_sign_fraction", "negative-frequency fraction"),
    ("speed_err_median_mps", "speed error median (m/s)"),
    ("pred200ms_vx_sq_err_mean_1e-2", "0.2 s-ahead v_x error (1e-2 (m/s)^2)"),
    ("pred200ms_vz_sq_err_mean_1e-2", "0.2 s-ahead v_z error (1e-2 (m/s)^2)"),
)


#: The metrics that depend on the reference: reported over the trusted references too.
REFERENCE_KEYS = ("f_err_median_hz", "speed_err_median_mps")


def trusted(item) -> bool:
    """True when an item's reference can be trusted (the synthetic truth always is)."""
    return item.item.truth is not None or bool(item.reference_quality.trusted)


def reference_counts(evaluation: Evaluation) -> tuple[int, int]:
    """(recordings with a trusted reference, recordings)."""
    return sum(trusted(r) for r in evaluation.items), len(evaluation.items)


def median_and_worst(
    evaluation: Evaluation, estimator: str, key: str, higher_is_better: bool = False, by_magnitude: bool = False
):
    """(median, worst value, worst recording's name, recordings with a value) of ``key`` over the
    recordings of ``estimator``; the worst is the highest value (the lowest with ``higher_is_better``,
    the farthest from 0 with ``by_magnitude``, e.g. a signed lag). NaN values are left out;
    (nan, nan, "", 0) without any."""
    pairs = [
        (float(r.metrics[estimator].get(key, np.nan)), r.item.name) for r in evaluation.items if estimator in r.metrics
    ]
    pairs = [(v, n) for v, n in pairs if not math.isnan(v)]
    if not pairs:
        return float("nan"), float("nan"), "", 0
    values = np.array([v for v, _ in pairs])
    if by_magnitude:
        i = int(np.argmax(np.abs(values)))
    else:
        i = int(np.argmin(values) if higher_is_better else np.argmax(values))
    return float(np.median(values)), float(values[i]), pairs[i][1], len(pairs)


def median_and_worst_markdown(
    evaluation: Evaluation, keys, higher_is_better=frozenset(), by_magnitude=frozenset()
) -> str:
    """A table of (column, label) rows: per estimator the median over recordings and the worst recording
    (its value and name); ``higher_is_better`` and ``by_magnitude``: the columns whose worst is the lowest
    value, or the farthest from 0."""
    head = " | ".join(f"{md_text(e)}: median | {md_text(e)}: worst (recording)" for e in evaluation.estimators)
    lines = [f"| over recordings | {head} |", "|---|" + "---:|---|" * len(evaluation.estimators)]
    for key, label in keys:
        cells = []
        for est in evaluation.estimators:
            med, worst, name, n = median_and_worst(evaluation, est, key, key in higher_is_better, key in by_magnitude)
            if n == 0:
                cells += ["n/a", "n/a"]
            else:
                cells += [f"{med:.3g} (n={n})", f"{worst:.3g} ({md_code(name)})"]
        lines.append(f"| {label} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def summary_markdown(evaluation: Evaluation) -> str:
    """Median over recordings of the main metrics and the worst recording, per estimator.

    Where some references are not trusted (:class:`~yoyogait.pipeline.events.ReferenceQuality`), the
    metrics against the reference (:data:`REFERENCE_KEYS`) follow again over the trusted ones only,
    and a line counts them and names those left out.
    """
    return with_trusted_part(evaluation, SUMMARY_KEYS, REFERENCE_KEYS)


def with_trusted_part(
    evaluation: Evaluation, keys, reference_keys, higher_is_better=frozenset(), by_magnitude=frozenset()
) -> str:
    """:func:`median_and_worst_markdown` of ``keys``; where some references are not trusted, the
    ``reference_keys`` among them again over the trusted recordings only, and a line that counts them
    and names those left out (and why)."""
    text = median_and_worst_markdown(evaluation, keys, higher_is_better, by_magnitude)
    n_trusted, n_all = reference_counts(evaluation)
    if n_trusted == n_all:
        return text
    kept = dataclasses.replace(evaluation, items=[r for r in evaluation.items if trusted(r)])
    again = [(key, f"{label}, {n_trusted} trusted references") for key, label in keys if key in reference_keys]
    left = [r for r in evaluation.items if not trusted(r)]
    return "\n".join(
        [
            text,
            "",
            median_and_worst_markdown(kept, again, higher_is_better, by_magnitude),
            "",
            f"References trusted on {n_trusted} of {n_all} recordings; not trusted: "
            + "; ".join(f"{md_code(r.item.name)} ({md_text(r.reference_quality.reason)})" for r in left)
            + ".",
        ]
    )
