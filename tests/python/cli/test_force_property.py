"""--force over any file tree: whatever a report folder holds (the user's files, links into and out of it,
FIFOs, a forged or stale list of files), replacing the report changes nothing but what yoyogait wrote
there, and a refusal changes nothing at all."""

from __future__ import annotations

import hashlib
import os
import shutil
import stat
import tempfile
from pathlib import Path

from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

from yoyogait import _files
from yoyogait.errors import OutputError

MARKER = _files.MARKER
REPORT_NAMES = ["index.md", "recordings.csv", "table1_a.csv", "figures/a.png", "figures/b.png", "figures/sub/c.png"]
USER_NAMES = ["notes.md", "figures/mine.png", "figures/sub/mine.txt", "data/raw.csv"]
ALL_NAMES = REPORT_NAMES + USER_NAMES + ["figures", "figures/sub", MARKER]
LINK_TARGETS = ["../outside/a.txt", "../outside/dir", "../../outside/dir", "nowhere", "index.md", "/"]


def snapshot(root: Path) -> dict[str, tuple]:
    """Every path below ``root`` (links not followed): its type and, for a regular file, the sha256 of its
    content, for a link its target."""
    out: dict[str, tuple] = {}
    for folder, dirs, files in os.walk(root):
        for name in dirs + files:
            p = Path(folder) / name
            mode = os.lstat(p).st_mode
            rel = p.relative_to(root).as_posix()
            if stat.S_ISREG(mode):
                out[rel] = ("file", hashlib.sha256(p.read_bytes()).hexdigest())
            elif stat.S_ISLNK(mode):
                out[rel] = ("link", os.readlink(p))
            else:
                out[rel] = (stat.S_IFMT(mode), None)
    return out


def real_parent(out: Path, rel: str) -> Path | None:
    """The folder of ``out/rel``, made of real folders (made where missing); None if a link or a file is on the way."""
    folder = out
    for part in rel.split("/")[:-1]:
        folder = folder / part
        st = _files._lstat(folder)
        if st is None:
            folder.mkdir()
        elif not stat.S_ISDIR(st.st_mode):
            return None
    return folder


def clear(path: Path) -> None:
    """Remove whatever is at ``path`` (a folder with all it holds), without following a link."""
    st = _files._lstat(path)
    if st is None:
        return
    if stat.S_ISDIR(st.st_mode):
        shutil.rmtree(path)
    else:
        path.unlink()


operations = st.one_of(
    st.tuples(st.just("user file"), st.sampled_from(REPORT_NAMES + USER_NAMES), st.binary(max_size=8)),
    st.tuples(st.just("link"), st.sampled_from(ALL_NAMES), st.sampled_from(LINK_TARGETS)),
    st.tuples(st.just("fifo"), st.sampled_from(REPORT_NAMES + USER_NAMES), st.just(b"")),
    st.tuples(
        st.just("forge"),
        st.sampled_from(USER_NAMES + ["../outside/a.txt", "/etc/hostname", "../sibling.txt", "figures"]),
        st.sampled_from([b"name", b"hash"]),
    ),
    st.tuples(st.just("delete"), st.sampled_from(REPORT_NAMES + ["figures"]), st.just(b"")),
)


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    first=st.lists(st.sampled_from(REPORT_NAMES), min_size=1, unique=True),
    second=st.lists(st.sampled_from(REPORT_NAMES), min_size=1, unique=True),
    ops=st.lists(operations, max_size=6),
    content=st.binary(min_size=1, max_size=8),
)
def test_force_changes_only_what_yoyogait_wrote(first, second, ops, content):
    """Over random trees (the user's files, links in and out of the folder, FIFOs, forged list lines),
    check_output_folder + install_folder with --force leave every path that is not an unchanged file of
    yoyogait's list as it was (outside the folder: everything), and change nothing when they refuse."""
    with tempfile.TemporaryDirectory() as tmp_name:
        base = Path(tmp_name) / "base"
        (base / "outside" / "dir").mkdir(parents=True)
        (base / "outside" / "a.txt").write_bytes(b"outside")
        (base / "outside" / "dir" / "b.png").write_bytes(b"outside too")
        (base / "sibling.txt").write_bytes(b"beside")
        out = base / "out"
        staging = Path(tmp_name) / "staging"

        def stage(names, data) -> Path:
            clear(staging)
            for name in names:
                (staging / name).parent.mkdir(parents=True, exist_ok=True)
                (staging / name).write_bytes(data + name.encode())
            return staging

        _files.install_folder(stage(first, b"old "), out)
        own = set(first)  # files of yoyogait's list, still as it wrote them
        for op, name, arg in ops:
            target = out / name
            if op == "forge":
                marker = out / MARKER
                if _files._lstat(marker) is not None and stat.S_ISREG(os.lstat(marker).st_mode):
                    with open(marker, "a") as fh:
                        fh.write(f"{name}\n" if arg == b"name" else f"{'a' * 64}  {name}\n")
                continue
            if real_parent(out, name) is None:
                continue
            if op == "user file":
                if _files._lstat(target) is not None and stat.S_ISDIR(os.lstat(target).st_mode):
                    continue
                clear(target)
                target.write_bytes(b"user " + arg)
            elif op == "link":
                clear(target)
                target.symlink_to(arg)
            elif op == "fifo":
                clear(target)
                os.mkfifo(target)
            elif op == "delete":
                clear(target)
            own = {n for n in own if n != name and not n.startswith(name + "/")}
        before = snapshot(base)
        try:
            _files.check_output_folder(out, force=True)
            _files.install_folder(stage(second, content), out)
            refused = False
        except OutputError as exc:
            refused = True
            assert "\n" not in str(exc)
        after = snapshot(base)
        event("refused" if refused else "replaced")
        if refused:
            assert after == before
            return
        for rel, what in before.items():
            inside = rel.startswith("out/")
            name = rel[len("out/") :]
            if inside and (name in own or name == MARKER or what[0] == stat.S_IFDIR):
                continue
            assert after.get(rel) == what, (rel, what, after.get(rel))
        for name in second:
            assert after[f"out/{name}"] == ("file", hashlib.sha256(content + name.encode()).hexdigest())
        appeared = {rel for rel in after if rel not in before}
        allowed = {f"out/{n}" for n in second} | {"out/" + MARKER}
        allowed |= {f"out/{n.rsplit('/', k)[0]}" for n in second for k in (1, 2) if n.count("/") >= k}
        assert appeared <= allowed, appeared - allowed
        assert _files.written_files(out) == sorted(second)
