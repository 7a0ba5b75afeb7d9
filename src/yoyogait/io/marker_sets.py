"""Which names are the pelvis, a hand and a foot: the marker-set table as data.

The table is ``marker_sets.json`` beside this module (shipped in the wheel):
whole names per set (Plug-in Gait/CGM, IOR/CAST, ISB, Xsens MVN, OpenCap,
MoCap Toolbox, Qualisys, OptiTrack) and generic words composed with a side
(``L``/``left`` before or after ``heel``, ``asis``, ``wrist``...).  Users add
their own sets with a file of the same shape, named by the environment
variable ``YOYOGAIT_MARKER_SETS`` (several joined by the path separator) or
given to :func:`add_marker_sets`.  Names are compared normalised: lower case,
letters and digits only, without a ``Subject:`` prefix, a skeleton prefix
(``Skeleton_Hip``, ``Skeleton 001_LFoot``) or the decorations the table strips
(Xsens ``p``/``j`` point prefixes, OpenCap's ``_study``).
"""

from __future__ import annotations

import functools
import json
import os
import re
from collections.abc import Sequence
from dataclasses import dataclass, field
from importlib import resources

from .. import _reading
from ..errors import InputError

__all__ = [
    "MARKER_SETS_ENV",
    "HAND_KINDS",
    "FOOT_KINDS",
    "SIDES",
    "MarkerKnowledge",
    "add_marker_sets",
    "marker_knowledge",
    "normalise_name",
    "roles",
    "pelvis_names",
]

#: Environment variable naming extra marker-set files (JSON, the shape of io/marker_sets.json), path-separated.
MARKER_SETS_ENV = "YOYOGAIT_MARKER_SETS"
_BUILTIN_SETS = "marker_sets.json"
_added_files: list[str] = []

#: Ranks of the kinds of hand and foot points: lower is preferred.
HAND_KINDS = ("hand", "finger", "wrist")
FOOT_KINDS = ("heel", "ankle", "toe")
SIDES = ("left", "right")


@dataclass
class MarkerKnowledge:
    """The marker-set table (io/marker_sets.json plus the user's files), ready for matching."""

    strip: list  # compiled patterns removed from a name before it is normalised
    not_prefixes: set
    sides: dict  # side -> tokens ("l", "left")
    suffixes: tuple
    pelvis_sided: set
    pelvis_words: set
    pelvis_patterns: list
    roots: list  # normalised root-joint names, in order of preference
    hand_words: dict  # word -> rank
    foot_words: dict  # word -> rank
    exact: dict  # normalised name -> list of (role, side, rank); role: pelvis, root, hand, foot
    sets: dict  # the named sets as written (for documentation and tests)
    files: list
    roles_of: dict = field(default_factory=dict)  # name -> its roles, as found (every recording repeats names)


def add_marker_sets(path) -> None:
    """Extend the marker-set table with a JSON file of the shape of ``io/marker_sets.json`` (for this process)."""
    path = str(path)
    _read_table(path)  # InputError now rather than at the first lookup
    _added_files.append(path)


def marker_knowledge() -> MarkerKnowledge:
    """The marker-set table: the built-in one, then the files of $YOYOGAIT_MARKER_SETS, then :func:`add_marker_sets`."""
    extra = [f for f in os.environ.get(MARKER_SETS_ENV, "").split(os.pathsep) if f.strip()]
    return _knowledge(tuple(extra + _added_files))


@functools.lru_cache(maxsize=8)
def _knowledge(files: tuple) -> MarkerKnowledge:
    tables = [json.loads(resources.files("yoyogait.io").joinpath(_BUILTIN_SETS).read_text(encoding="utf-8"))]
    tables += [_read_table(f) for f in files]
    k = MarkerKnowledge([], set(), {side: [] for side in SIDES}, (), set(), set(), [], [], {}, {}, {}, {}, list(files))
    for table in tables:
        k.strip += [re.compile(x) for x in table.get("strip", [])]
        k.not_prefixes |= {normalise_name(x) for x in table.get("not_prefixes", [])}
        generic = table.get("generic", {})
        for side, tokens in generic.get("sides", {}).items():
            k.sides.setdefault(side, []).extend(t for t in tokens if t not in k.sides.get(side, []))
        k.suffixes = tuple(dict.fromkeys(k.suffixes + tuple(generic.get("suffixes", []))))
        pelvis = generic.get("pelvis", {})
        k.pelvis_sided |= set(pelvis.get("sided_words", []))
        k.pelvis_words |= set(pelvis.get("words", []))
        k.pelvis_patterns += [re.compile(x) for x in pelvis.get("patterns", [])]
        k.roots += [normalise_name(r) for r in pelvis.get("roots", []) if normalise_name(r) not in k.roots]
        for kinds, target, group in ((HAND_KINDS, k.hand_words, "hand"), (FOOT_KINDS, k.foot_words, "foot")):
            for rank, kind in enumerate(kinds):
                for word in generic.get(group, {}).get(kind, []):
                    target[word] = min(rank, target.get(word, rank))
        for set_name, spec in table.get("sets", {}).items():
            k.sets[set_name] = spec
            for name in spec.get("pelvis", []):
                k.exact.setdefault(_exact_key(name, k), []).append(("pelvis", None, 0))
            for name in spec.get("root", []):  # after the generic roots, whose order is a preference
                k.exact.setdefault(_exact_key(name, k), []).append(("root", None, 100))
            for side, names in spec.get("hips", {}).items():
                for name in names:
                    k.exact.setdefault(_exact_key(name, k), []).append(("hips", side, 0))
            for role, rank in (("hand", 0), ("wrist", 2)):
                for side, names in spec.get(role, {}).items():
                    for name in names:
                        k.exact.setdefault(_exact_key(name, k), []).append(("hand", side, rank))
            for side, kinds in spec.get("feet", {}).items():
                for kind, names in kinds.items():
                    for name in names:
                        k.exact.setdefault(_exact_key(name, k), []).append(("foot", side, FOOT_KINDS.index(kind)))
    return k


def _read_table(path) -> dict:
    try:  # a regular file of at most 16 MiB, nested at most 64 deep
        table = _reading.read_json(path, 16 * 2**20, "marker-set file")
    except InputError as exc:
        raise InputError(f"marker-set file (${MARKER_SETS_ENV}) {exc}") from None
    if not isinstance(table, dict) or not set(table) & {"sets", "generic", "strip"}:
        raise InputError(f"marker-set file {path}: expected an object with 'sets' (see docs/input.md)")
    for kinds in (spec.get("feet", {}) for spec in table.get("sets", {}).values()):
        for side, by_kind in kinds.items():
            bad = set(by_kind) - set(FOOT_KINDS)
            if side not in SIDES or bad:
                raise InputError(f"marker-set file {path}: feet must be left/right of heel/ankle/toe, not {side} {bad}")
    return table


def _exact_key(name: str, k: MarkerKnowledge) -> str:
    return _keys(name, k)[0]


def _keys(name: str, k: MarkerKnowledge) -> list[str]:
    """Normalised forms of a name to match, best first: whole, then without a skeleton prefix (``Skeleton_Hip``)."""
    bare = name.rsplit(":", 1)[-1]
    for pattern in k.strip:
        bare = pattern.sub("", bare)
    keys = [normalise_name(bare)]
    parts = re.split(r"[_ ]", bare)
    for i in range(1, len(parts)):
        prefix = normalise_name("".join(parts[:i]))
        if prefix and prefix not in k.not_prefixes and not any(prefix in t for t in k.sides.values()):
            rest = normalise_name("".join(parts[i:]))
            if rest and rest not in keys:
                keys.append(rest)
    return [key for key in keys if key]


def _sided(key: str, words: dict | set, k: MarkerKnowledge, *, optional: bool = False):
    """(side, word) if ``key`` is a side token before or after one of ``words`` (plus a suffix), else None."""
    parses = [(None, key)] if optional else []
    for side, tokens in k.sides.items():
        for tag in tokens:
            if key.startswith(tag):
                parses.append((side, key[len(tag) :]))
            if key.endswith(tag):
                parses.append((side, key[: -len(tag)]))
    for side, rest in parses:
        for word in words:
            if rest == word or (rest.startswith(word) and rest[len(word) :] in k.suffixes):
                return side, word
    return None


def _roles(name: str, k: MarkerKnowledge) -> list[tuple[str, str | None, int]]:
    """What a name is: (role, side, rank) for pelvis markers, root joints, hands and feet."""
    found = k.roles_of.get(name)
    if found is None:
        found = k.roles_of[name] = tuple(_find_roles(name, k))
    return list(found)


def _find_roles(name: str, k: MarkerKnowledge) -> list[tuple[str, str | None, int]]:
    for key in _keys(name, k):
        roles = list(k.exact.get(key, []))
        if _sided(key, k.pelvis_sided, k, optional=True) or key in k.pelvis_words:
            roles.append(("pelvis", None, 0))
        if any(p.match(key) for p in k.pelvis_patterns):
            roles.append(("pelvis", None, 0))
        if key in k.roots:
            roles.append(("root", None, k.roots.index(key)))
        for role, words in (("hand", k.hand_words), ("foot", k.foot_words)):
            parsed = _sided(key, words, k)
            if parsed:
                roles.append((role, parsed[0], words[parsed[1]]))
        if roles:
            return roles
    return []


def normalise_name(name: str) -> str:
    """Lower case, letters and digits only, without a ``Subject:`` prefix."""
    return re.sub(r"[^a-z0-9]", "", name.rsplit(":", 1)[-1].lower())


def roles(name: str) -> list[tuple[str, str | None, int]]:
    """What a name is, by the table: (role, side, rank) with role "pelvis", "root", "hips", "hand" or "foot"."""
    return _roles(name, marker_knowledge())


def pelvis_names(names: Sequence[str]) -> tuple[list[str], str]:
    """(the pelvis markers, "pelvis markers") if any, else ([the preferred root joint], "root joint"), else
    ([the left and right hip joint centres], "hip joints"), else ([], "")."""
    k = marker_knowledge()
    found = {n: _roles(n, k) for n in names}
    markers = [n for n in names if any(r[0] == "pelvis" for r in found[n])]
    if markers:
        return markers, "pelvis markers"
    roots = [
        (min(r[2] for r in found[n] if r[0] == "root"), i, n)
        for i, n in enumerate(names)
        if any(r[0] == "root" for r in found[n])
    ]
    if roots:
        return [min(roots)[2]], "root joint"
    hips = {side: [n for n in names if ("hips", side, 0) in found[n]] for side in SIDES}
    if all(hips.values()):  # the hip joint centres of both sides (video keypoints): their midpoint
        return [hips[side][0] for side in SIDES], "hip joints"
    return [], ""
