"""The C3D reader's numpy decoding of the points against ezc3d's, on every real C3D file."""

from __future__ import annotations

import numpy as np
import pytest

import corrupt_mutants as cm
from yoyogait.errors import InputError
from yoyogait.io import c3d as c3d_module
from yoyogait.io.c3d import read_c3d


def _c3d_files(datasets_dir):
    files = sorted(f for f in datasets_dir.rglob("*") if f.suffix.lower() == ".c3d" and f.is_file())
    assert files, f"no C3D file under {datasets_dir}"
    return files


def _same_bits(a: np.ndarray, b: np.ndarray) -> bool:
    return a.shape == b.shape and a.dtype == b.dtype and np.array_equal(a.view(np.uint64), b.view(np.uint64))


def test_fast_decoding_matches_ezc3d_points(datasets_dir):
    """Every real Intel C3D file and DEC file of integer data is decoded by numpy, to ezc3d's exact points and
    invalid marks."""
    import ezc3d

    decoded = 0
    for path in _c3d_files(datasets_dir):
        raw = path.read_bytes()
        header_scale = c3d_module._check_header(path, raw)
        fast = c3d_module._read_fast(raw, header_scale)
        processor = raw[512 * (raw[0] - 1) + 3]
        if header_scale is not None and (processor == 84 or (processor == 85 and header_scale > 0)):
            assert fast is not None, f"{path.name}: read by ezc3d whole"
        if fast is None:
            continue
        decoded += 1
        _, xyz, negative_residual = fast
        c = ezc3d.c3d(str(path), extract_forceplat_data=False)
        points = np.transpose(c["data"]["points"][:3], (2, 1, 0))
        residuals = np.asarray(c["data"]["meta_points"]["residuals"]).reshape(points.shape[1], points.shape[0]).T
        assert np.array_equal(negative_residual, residuals < 0), path.name
        valid = ~negative_residual
        assert np.all(np.isnan(points[~valid])), path.name
        assert np.array_equal(xyz[valid].view(np.uint64), points[valid].astype(float).view(np.uint64)), path.name
    assert decoded > 0


def test_fast_and_ezc3d_readings_are_identical(datasets_dir, monkeypatch):
    """read_c3d gives bit-identical positions (NaN alike), names, rate, time and metadata by either path."""
    files = _c3d_files(datasets_dir)
    fast = [read_c3d(f) for f in files]
    monkeypatch.setattr(c3d_module, "_read_fast", lambda raw, header_scale: None)
    for path, a in zip(files, fast):
        b = read_c3d(path)
        assert _same_bits(a.positions_m, b.positions_m), path.name
        assert a.point_names == b.point_names, path.name
        assert a.rate_hz == b.rate_hz and _same_bits(a.time_s, b.time_s), path.name
        assert a.up_axis == b.up_axis and a.metadata == b.metadata, path.name


def test_short_data_falls_back_to_ezc3d(datasets_dir, tmp_path):
    """A file whose data blocks hold fewer bytes than the frames need is not decoded by numpy."""
    path = datasets_dir / "c3d_org_samples" / "sample26_Qualisys_Walking_Hybrid_1_1.c3d"
    if not path.is_file():
        pytest.skip(f"{path} is absent")
    raw = path.read_bytes()
    header_scale = c3d_module._check_header(path, raw)
    assert c3d_module._read_fast(raw, header_scale) is not None
    assert c3d_module._read_fast(raw[: len(raw) - 4096], header_scale) is None


def _outcome(path):
    try:
        r = read_c3d(path)
    except InputError as exc:
        return ("error", str(exc))
    return ("read", r.positions_m.tobytes(), r.point_names, r.rate_hz, repr(r.metadata), r.up_axis)


def test_corrupt_copies_read_alike_by_both_paths(datasets_dir, tmp_path, monkeypatch):
    """Corrupt copies of the C3D files (cut, flipped bytes, zeroed blocks, odd header numbers, bogus data)
    give the same recording or the same error whether numpy decodes the points or ezc3d reads it whole."""
    files = _c3d_files(datasets_dir)
    operators = [cm._truncate, cm._flip_bytes, cm._zero_block, cm._c3d_header_number, cm._c3d_data_float]
    fast_path = c3d_module._read_fast
    decoded = 0
    for i in range(150):
        source = files[i % len(files)]
        data, detail = operators[(i // len(files)) % len(operators)](
            source.read_bytes(), np.random.default_rng((11, i))
        )
        path = tmp_path / f"m{i:03d}_{source.name}"
        path.write_bytes(data)
        monkeypatch.setattr(c3d_module, "_read_fast", fast_path)
        fast = _outcome(path)
        try:
            decoded += fast_path(data, c3d_module._check_header(path, data)) is not None
        except InputError:
            pass
        monkeypatch.setattr(c3d_module, "_read_fast", lambda raw, header_scale: None)
        assert _outcome(path) == fast, f"{source.name}: {detail}"
    assert decoded >= 50  # the comparison exercised the numpy path, not only the fallback


def test_parameters_running_into_the_data_are_read_by_ezc3d_whole(datasets_dir, tmp_path, monkeypatch):
    """A header whose data start cuts the parameter records short leaves the file to ezc3d whole (the copy
    ezc3d would parse lacks bytes it reads), with the same outcome as before."""
    source = datasets_dir / "c3d_org_samples" / "sample26_Qualisys_Walking_Hybrid_1_1.c3d"
    if not source.is_file():
        pytest.skip(f"{source} is absent")
    data = bytearray(source.read_bytes())
    first = data[0]
    parameters_end = c3d_module._parameters_end(bytes(data))
    block = parameters_end // 512 + 1  # the (1-based) block where the parameter records end
    assert block > first + 1
    data[512 * (first - 1) + 2] = block - first  # parameter blocks in the header: up to that block
    data[16:18] = block.to_bytes(2, "little")  # the data start at that block, inside the records
    path = tmp_path / "short_parameters.c3d"
    path.write_bytes(bytes(data))
    assert c3d_module._parameters_end(bytes(data)) > 512 * (block - 1)
    assert c3d_module._read_fast(bytes(data), c3d_module._check_header(path, bytes(data))) is None
    fast = _outcome(path)
    monkeypatch.setattr(c3d_module, "_read_fast", lambda raw, header_scale: None)
    assert _outcome(path) == fast


def test_parameter_records_end_where_ezc3d_stops_reading(datasets_dir):
    """ezc3d parses the same POINT group and layout from the bytes up to the computed end of the parameter
    records as from those up to the data start (so the end is not placed too early)."""
    import ezc3d

    for path in _c3d_files(datasets_dir):
        raw = path.read_bytes()
        end = c3d_module._parameters_end(raw)
        data_start = 512 * (int.from_bytes(raw[16:18], "little") - 1)
        assert end is not None and end <= data_start, path.name
        short, layout = c3d_module._parse_parameters(ezc3d, raw[:end])
        full, full_layout = c3d_module._parse_parameters(ezc3d, raw[:data_start])
        assert layout == full_layout, path.name
        assert short["header"] == full["header"], path.name
        for name, entry in full["parameters"]["POINT"].items():
            assert np.array_equal(np.asarray(short["parameters"]["POINT"][name]["value"]), np.asarray(entry["value"]))
