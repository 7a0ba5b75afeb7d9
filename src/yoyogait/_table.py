"""Columns of per-sample values as a CSV file or a pandas DataFrame (pandas is the optional extra
``yoyogait[pandas]``)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ._files import atomic_file


def to_dataframe(columns: dict):
    """A pandas DataFrame of ``columns`` (name -> 1-D array, all of one length)."""
    try:
        import pandas as pd
    except ImportError:
        raise ImportError(
            "to_dataframe() needs pandas, which yoyogait installs as an extra: pip install 'yoyogait[pandas]'"
        ) from None
    return pd.DataFrame(columns)


def _format(values: np.ndarray) -> str:
    if values.dtype == bool:
        return "%d"
    if np.issubdtype(values.dtype, np.integer):
        return "%d"
    return "%.6g"


def write_csv(path, columns: dict, time_format: str = "%.4f") -> Path:
    """``columns`` as a CSV with a header line, written through a temporary file; returns the path."""
    path = Path(path)
    names = list(columns)
    arrays = [np.asarray(columns[n]) for n in names]
    formats = [time_format if n == "time_s" else _format(a) for n, a in zip(names, arrays)]
    table = np.column_stack([a.astype(float) for a in arrays]) if arrays else np.empty((0, 0))
    atomic_file(
        path,
        lambda p: np.savetxt(p, table, delimiter=",", header=",".join(names), comments="", fmt=formats),
    )
    return path
