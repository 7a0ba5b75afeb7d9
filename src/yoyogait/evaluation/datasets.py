"""Data sets to evaluate on: the built-in synthetic lab, a folder of recordings, or a manifest.

A data set is a list of :class:`Item` (a recording to load, its subject and walk
type, and the ground truth where there is one).  The manifest follows the schema of
``shared/datasets/manifest.json`` (see the README).
"""

from __future__ import annotations

import dataclasses
import functools
import json
import tempfile
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from .. import io, synthetic
from ..errors import InputError
from ..io.recording import Recording
from ..synthetic import SyntheticTruth

__all__ = ["Item", "READABLE", "synthetic_items", "manifest_items", "folder_items", "resolve_dataset", "shipped"]

READABLE = tuple(io.READERS)


@dataclass
class Item:
    """One recording of a data set, not loaded yet."""

    name: str  # file name (or the synthetic walk's name)
    subject: str  # a column of Table I
    walk: str  # a row group of Table I
    load: Callable[[], Recording]
    truth: SyntheticTruth | None = None  # for synthetic walks
    pelvis: list | None = None  # points to average for the pelvis centre (else found by name)
    feet: list | dict | None = None  # foot points: {"left": [...], "right": [...]} or a list (sides from the names)
    up_axis: str | None = None
    synthetic: bool = False


def _recording_of(walk) -> Recording:
    # A named function rather than a lambda: items stay picklable (for worker processes).
    return walk.recording


def synthetic_item(walk) -> Item:
    """An item of one synthetic walk (SYNTHETIC data), with its truth."""
    return Item(
        name=walk.name,
        subject=walk.subject.name,
        walk=walk.walk_type,
        load=functools.partial(_recording_of, walk),
        truth=walk.truth,
        pelvis=list(synthetic.PELVIS_MARKERS),
        feet=list(synthetic.HEEL_MARKERS),
        up_axis="z",
        synthetic=True,
    )


def synthetic_items(seed: int = 0, rate_hz: float = 100.0) -> list[Item]:
    """The built-in synthetic lab: 3 virtual subjects x 5 walk types (SYNTHETIC data)."""
    items = [synthetic_item(walk) for walk in synthetic.default_lab(seed=seed, rate_hz=rate_hz)]
    return items


def manifest_items(path) -> tuple[list[Item], list[tuple[str, str]]]:
    """Items of a manifest (schema of shared/datasets/manifest.json); paths are relative to it.

    Returns the items whose file exists and (name, problem) for each that does not.
    """
    path = Path(path)
    try:
        doc = json.loads(path.read_text())
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"cannot read manifest {path}: {exc}") from None
    except json.JSONDecodeError as exc:
        raise InputError(f"manifest {path} is not valid JSON: {exc.msg} at line {exc.lineno}") from None
    entries = doc.get("recordings") if isinstance(doc, dict) else None
    if not isinstance(entries, list):
        raise InputError(f"manifest {path} has no list 'recordings'")
    items, missing = [], []
    for n, entry in enumerate(entries):
        if not isinstance(entry, dict) or not isinstance(entry.get("path"), str):
            missing.append((f"entry {n}", "has no 'path'"))
            continue
        file = path.parent / entry["path"]
        if not file.is_file():
            missing.append((entry["path"], f"file not found: {file}"))
            continue
        overrides: dict = {}
        if entry.get("length_unit_m") is not None:
            overrides["length_unit_m"] = float(entry["length_unit_m"])
        if entry.get("vertical_axis"):
            overrides["up_axis"] = entry["vertical_axis"]
        feet = entry.get("feet")
        if feet is not None and not isinstance(feet, (list, dict)):
            missing.append((entry["path"], '\'feet\' must be a list of names or {"left": [...], "right": [...]}'))
            continue
        items.append(
            Item(
                name=Path(entry["path"]).name,
                subject=Path(entry["path"]).parent.name or "recordings",
                walk=entry.get("walk") or "unknown",
                load=functools.partial(io.read, file, **overrides),
                pelvis=entry.get("pelvis"),
                feet=feet,
                up_axis=entry.get("vertical_axis"),
            )
        )
    return items, missing


def folder_items(path) -> list[Item]:
    """Every readable recording (any extension of :data:`yoyogait.io.READERS`) below a folder; pelvis and feet
    found by name."""
    path = Path(path)
    files = sorted(p for p in path.rglob("*") if p.is_file() and p.suffix.lower() in READABLE)
    if not files:
        raise InputError(f"no recordings ({', '.join(READABLE)}) in folder {path}")
    return [Item(name=f.name, subject=f.parent.name, walk="unknown", load=functools.partial(io.read, f)) for f in files]


def resolve_dataset(spec: str | None, seed: int = 0) -> tuple[list[Item], list[tuple[str, str]], bool]:
    """(items, problems, synthetic) for 'synthetic' (or None), a folder, or a manifest .json."""
    if spec is None or spec == "synthetic":
        return synthetic_items(seed=seed), [], True
    path = Path(spec)
    if path.is_dir():
        manifest = path / "manifest.json"
        if manifest.is_file():
            items, missing = manifest_items(manifest)
            return items, missing, False
        return folder_items(path), [], False
    if path.suffix.lower() == ".json":
        if not path.is_file():
            raise InputError(f"manifest not found: {path}")
        items, missing = manifest_items(path)
        return items, missing, False
    if not path.exists():
        raise InputError(f"data set not found: {spec} (give 'synthetic', a folder or a manifest .json)")
    raise InputError(f"not a data set: {spec} (give 'synthetic', a folder or a manifest .json)")


def read_shipped(data: bytes, name: str, **overrides) -> Recording:
    """Read a recording from the bytes of its file (``name`` gives the extension and the messages)."""
    with tempfile.TemporaryDirectory(prefix="yoyogait-") as folder:
        path = Path(folder) / Path(name).name
        path.write_bytes(data)
        return io.read(path, **overrides)


def shipped(item: Item) -> Item:
    """The item with its file's bytes inside it, for workers that do not see the file (Dask).

    Items that are not read from a file (the synthetic lab) already carry their data.
    """
    return dataclasses.replace(item, load=_ship(item.load))


def _ship(load):
    """``load`` with io.read(path) replaced by a read of the file's bytes, also inside a wrapping
    partial (such as one that checks the points after reading)."""
    if not isinstance(load, functools.partial) or not load.args:
        return load
    if load.func is io.read:
        path = Path(load.args[0])
        try:
            data = path.read_bytes()
        except OSError as exc:
            raise InputError(f"cannot read {path}: {exc.strerror or exc}") from None
        return functools.partial(read_shipped, data, str(path), **load.keywords)
    inner = _ship(load.args[0])
    if inner is load.args[0]:
        return load
    return functools.partial(load.func, inner, *load.args[1:], **load.keywords)
