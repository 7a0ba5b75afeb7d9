"""C3D files (Vicon, Qualisys, Motion Analysis, Codamotion, ...) through ``ezc3d``.

* Length unit from ``POINT:UNITS`` (mm when the parameter is absent, the
  format's default; ``length_unit_m=`` overrides).
* A point is missing where its residual is negative (the C3D convention) or
  where all three coordinates are exactly zero (what several systems write
  for an occluded marker); both become NaN.
* Points that are not positions (the angles, forces, moments, powers and
  scalars a modelling step stores in the POINT group, listed in
  ``POINT:ANGLES`` etc.) are left out; their names go to
  ``metadata["excluded_points"]``.  Modelled positions (e.g. Plug-in Gait's
  PELO or a CGM pelvis origin) stay.
* The up axis comes from ``POINT:Y_SCREEN`` when it names a positive axis
  (it is the axis drawn upwards on screen), else it is left to detection.
* ezc3d quietly reads what there is of a truncated file, so the frame count
  the header promises is checked against the file size.
* Speed: ezc3d builds an object for every point and analog sample of every
  frame, most of the time spent reading a file with 1000 Hz analog channels.
  So ezc3d parses only the header and parameter blocks (it is handed a copy of
  them: it reads what there is of a file) and numpy decodes the points of the
  data blocks, value for value as ezc3d does (:func:`_decode_points`).  Files
  whose data that path does not cover (DEC floats, MIPS, rotations, fewer
  bytes than the frames need, anything ezc3d's header or parameters do not
  describe plainly) are read by ezc3d whole, as before.
"""

from __future__ import annotations

import os
import struct
import tempfile
from pathlib import Path

import numpy as np

from ..errors import InputError
from .recording import Recording, all_xyz, check_coordinates, check_rate, check_readable, gait_event, uniform_time
from .recording import length_unit_m as unit_of

__all__ = ["read_c3d"]

#: POINT parameters that list points whose values are not positions.
NON_POSITION_GROUPS = ("ANGLES", "FORCES", "MOMENTS", "POWERS", "SCALARS", "REACTIONS")


def read_c3d(
    path, *, length_unit_m: float | None = None, rate_hz: float | None = None, keep_non_positions: bool = False
) -> Recording:
    """Read the 3D points of a C3D file.

    ``keep_non_positions`` keeps the model outputs that are angles, forces, ...
    (scaled as if they were lengths, which is only useful for inspection).
    """
    import ezc3d

    p = check_readable(path)
    raw = p.read_bytes()
    header_scale = _check_header(p, raw)
    fast = _read_fast(raw, header_scale)
    if fast is not None:
        c, xyz, negative_residual = fast
    else:
        try:
            c = ezc3d.c3d(str(p), extract_forceplat_data=False)
        except (RuntimeError, OSError, ValueError, IndexError) as exc:
            raise InputError(f"{p}: not a readable C3D file ({_first_line(exc)})") from None

    point_group = c["parameters"].get("POINT", {})
    scale = _param(point_group, "SCALE")
    if scale and not (np.isfinite(float(scale[0])) and float(scale[0]) != 0):
        raise InputError(
            f"{p}: not a readable C3D file (POINT:SCALE is {float(scale[0])}; it must be a non-zero number)"
        )
    if scale and header_scale is not None and (header_scale < 0) != (float(scale[0]) < 0):
        raise InputError(
            f"{p}: not a readable C3D file (corrupt header: the point scale factor {header_scale:g} and "
            f"POINT:SCALE {float(scale[0]):g} disagree on whether the data are floats or integers)"
        )
    if fast is None:
        data = c["data"]["points"]  # 4 x points x frames
        n_points, n_frames = data.shape[1], data.shape[2]
        if n_frames == 0:
            raise InputError(f"{p}: the C3D file holds no frames")
        if n_points == 0:
            raise InputError(f"{p}: the C3D file holds no 3D points")
        xyz = np.transpose(data[:3], (2, 1, 0)).astype(float)  # frames x points x 3
        residuals = np.asarray(c["data"]["meta_points"]["residuals"]).reshape(n_points, n_frames).T
        negative_residual = residuals < 0
    n_frames, n_points = xyz.shape[0], xyz.shape[1]

    names = _labels(point_group, n_points)
    missing = negative_residual | all_xyz(xyz == 0.0) | ~all_xyz(np.isfinite(xyz))
    xyz[missing] = np.nan

    metadata: dict = {"format": "c3d"}
    units = _param(point_group, "UNITS")
    if length_unit_m is not None:
        scale_m = float(length_unit_m)
        metadata["length_unit_from"] = "override"
    elif units:
        scale_m = unit_of(units[0], str(p))
        metadata["length_unit_from"] = f"POINT:UNITS = {units[0].strip()}"
    else:
        scale_m = 0.001
        metadata["length_unit_from"] = "POINT:UNITS absent; mm assumed (the C3D default)"
    metadata["length_unit_m"] = scale_m
    xyz *= scale_m
    check_coordinates(xyz, names, p)

    keep = np.ones(n_points, dtype=bool)
    if not keep_non_positions:
        non_positions: set[str] = set()
        for group in NON_POSITION_GROUPS:
            non_positions.update(s.strip() for s in _param(point_group, group) or [])
        keep = np.array([n not in non_positions for n in names], dtype=bool)
        metadata["excluded_points"] = [n for n, k in zip(names, keep) if not k]
    names = _unique([n for n, k in zip(names, keep) if k])
    xyz = xyz[:, keep, :]

    file_rate = float(c["header"]["points"]["frame_rate"])
    rate = float(rate_hz) if rate_hz is not None else file_rate
    if not rate > 0:
        raise InputError(f"{p}: the C3D file has no point rate; pass capture_rate_hz=")
    rate = check_rate(rate, p, "capture_rate_hz override" if rate_hz is not None else "point rate in the C3D header")
    first_frame = int(c["header"]["points"]["first_frame"])
    metadata.update(first_frame=first_frame, file_rate_hz=file_rate)

    events = _events(c["parameters"].get("EVENT", {}), first_frame / rate)
    if events:
        metadata["events"] = events
    up_axis = None
    y_screen = _param(point_group, "Y_SCREEN")
    if y_screen:
        metadata["y_screen"] = y_screen[0].strip()
        axis = y_screen[0].strip().upper()
        if axis in ("+X", "+Y", "+Z", "X", "Y", "Z"):
            up_axis = axis[-1].lower()

    return Recording(
        positions_m=xyz,
        point_names=names,
        time_s=uniform_time(n_frames, rate),
        rate_hz=rate,
        up_axis=up_axis,
        source=str(p),
        metadata=metadata,
    )


def _read_fast(raw: bytes, header_scale: float | None):
    """(ezc3d's header and parameters, positions, negative residual) with the points decoded by numpy,
    or None when the file is left to ezc3d whole (see the module's docstring).

    ``raw`` is the file, already checked by :func:`_check_header`; ezc3d parses a copy of its header
    and parameter blocks, which gives the header as ezc3d settles it from the parameters (points
    from POINT:USED, frames from POINT:FRAMES, analog samples per frame from the rates).
    """
    import ezc3d

    if header_scale is None:
        return None
    processor = raw[512 * (raw[0] - 1) + 3]
    data_start = 512 * (struct.unpack("<H" if processor != 86 else ">H", raw[16:18])[0] - 1)
    if processor not in (84, 85) or not 512 <= data_start <= len(raw):
        return None  # MIPS: ezc3d rejects its points; keep its message
    end = _parameters_end(raw)
    if end is None or end > data_start:
        return None  # ezc3d's parse of the copy would lack bytes it reads from the file
    try:
        c, layout = _parse_parameters(ezc3d, raw[:data_start])
    except (RuntimeError, OSError, ValueError, IndexError):
        return None  # ezc3d's full read gives the message
    scale = _param(c["parameters"].get("POINT", {}), "SCALE")
    if not scale:
        return None
    point_scale = float(scale[0])
    n_points, n_frames = int(layout["points"]), int(layout["frames"])
    analog_values = int(layout["analog_values"])
    analog_float = layout["analog_float"]
    if (
        layout["rotations"]
        or 512 * (int(layout["data_start"]) - 1) != data_start
        or not (np.isfinite(point_scale) and point_scale != 0)
        or (point_scale < 0) != (header_scale < 0)
        or analog_float != (point_scale < 0)
        or (processor == 85 and point_scale < 0)  # DEC floats
        or n_points == 0
        or n_frames <= 0
    ):
        return None
    value_bytes = 4 if point_scale < 0 else 2
    frame_bytes = 4 * n_points * value_bytes + analog_values * value_bytes
    if data_start + n_frames * frame_bytes > len(raw):
        return None  # ezc3d reads what there is
    xyz, negative_residual = _decode_points(raw, data_start, n_frames, frame_bytes, n_points, point_scale)
    return c, xyz, negative_residual


def _parameters_end(raw: bytes) -> int | None:
    """Where the parameter records ezc3d reads end (a byte offset), following their chain as ezc3d
    does (Intel or DEC byte order); None when a record is not plain (an unknown type, a negative
    description length, a chain that leaves the file or does not end)."""
    pos = 512 * (raw[0] - 1) + 4  # after the parameter section's 4-byte header
    end = pos
    for _ in range(65536):
        if pos + 2 > len(raw):
            return None
        n_name, group_id = struct.unpack_from("<bb", raw, pos)
        if n_name == 0:
            return max(end, pos + 1)
        word = pos + 2 + abs(n_name)  # the offset to the next record, counted from this word
        if word + 2 > len(raw):
            return None
        offset = struct.unpack_from("<H", raw, word)[0]
        at = word + 2
        if group_id >= 0:  # a parameter: type, dimensions, values
            if at + 2 > len(raw):
                return None
            size, n_dims = struct.unpack_from("<bB", raw, at)
            if size not in (-1, 1, 2, 4) or at + 2 + n_dims > len(raw) or (n_dims == 0 and size == -1):
                return None  # (ezc3d reads a text of no dimensions out of bounds)
            count = int(np.prod(list(raw[at + 2 : at + 2 + n_dims]), dtype=np.int64))  # 1 for a scalar
            at += 2 + n_dims + abs(size) * count
        if at + 1 > len(raw) or raw[at] >= 128:
            return None
        at += 1 + raw[at]  # the description
        end = max(end, at)
        if offset == 0:
            return end
        pos = word + offset
    return None


def _decode_points(raw: bytes, start: int, n_frames: int, frame_bytes: int, n_points: int, point_scale: float):
    """The points of the data blocks as ezc3d decodes them (Intel, and DEC integers, which ezc3d reads
    as Intel's): frames x points x 3 float64, and where the residual is negative (frames x points).

    Each point is 4 values: x, y, z and a word whose residual part marks an invalid point when
    negative.  Floats (scale < 0): 4-byte floats, the residual is the upper 16-bit half of the fourth
    value.  Integers: 16-bit words times the scale, the residual is the fourth word's second byte.
    """
    frames = np.frombuffer(raw, dtype=np.uint8, count=n_frames * frame_bytes, offset=start).reshape(
        n_frames, frame_bytes
    )
    if point_scale < 0:
        values = frames[:, : 16 * n_points].view("<f4").reshape(n_frames, n_points, 4)
        xyz = values[:, :, :3].astype(float)
        words = frames[:, : 16 * n_points].view("<i2").reshape(n_frames, n_points, 8)
        negative_residual = words[:, :, 7] < 0
    else:
        values = frames[:, : 8 * n_points].view("<i2").reshape(n_frames, n_points, 4)
        xyz = values[:, :, :3].astype(float) * point_scale
        negative_residual = frames[:, : 8 * n_points].view(np.int8).reshape(n_frames, n_points, 8)[:, :, 7] < 0
    return xyz, negative_residual


def _parse_parameters(ezc3d, head: bytes):
    """ezc3d's reading of a file that holds only ``head`` (the header and parameter blocks): what
    :func:`read_c3d` uses of ``ezc3d.c3d(...)`` (the POINT and EVENT groups and the point header, converted as
    ezc3d's Python layer converts them), and ezc3d's header object.

    ezc3d reads from a path; an in-memory file (Linux) or else a temporary file holds the copy.
    """
    if hasattr(os, "memfd_create") and os.path.isdir("/proc/self/fd"):
        fd = os.memfd_create("yoyogait-c3d", getattr(os, "MFD_CLOEXEC", 0))
        try:
            os.write(fd, head)
            parsed = ezc3d.ezc3d.c3d(f"/proc/self/fd/{fd}", _options(ezc3d))
        finally:
            os.close(fd)
    else:
        with tempfile.TemporaryDirectory(prefix="yoyogait-c3d-") as folder:
            copy = Path(folder) / "head.c3d"
            copy.write_bytes(head)
            parsed = ezc3d.ezc3d.c3d(str(copy), _options(ezc3d))
    header = parsed.header()
    parameters = parsed.parameters()
    groups = {}
    for name in ("POINT", "EVENT"):
        if parameters.isGroup(name):
            group = parameters.group(name)
            groups[name] = {p.name(): {"value": _parameter_value(ezc3d, p)} for p in group.parameters()}
    points = {"frame_rate": header.frameRate(), "first_frame": header.firstFrame()}
    layout = {  # copied out: the header object lives inside `parsed`
        "points": header.nb3dPoints(),
        "frames": header.nbFrames(),
        "analog_values": header.nbAnalogByFrame() * header.nbAnalogs(),
        "analog_float": header.scaleFactor() < 0,
        "rotations": header.hasRotationalData(),
        "data_start": header.dataStart(),
    }
    return {"parameters": groups, "header": {"points": points}}, layout


def _options(ezc3d):
    """The options ``ezc3d.c3d(path)`` reads with."""
    return ezc3d.ezc3d.Options(ignoreBadFormatting=False, keepParametersTrailingSpaces=False)


def _parameter_value(ezc3d, parameter):
    """A parameter's value as ``ezc3d.c3d`` gives it (its ``add_parameter``)."""
    kind = parameter.type()
    if kind == ezc3d.ezc3d.BYTE:
        return np.array(parameter.valuesAsByte(), dtype="int").reshape(parameter.dimension(), order="F")
    if kind == ezc3d.ezc3d.INT:
        return np.array(parameter.valuesAsInt(), dtype="int").reshape(parameter.dimension(), order="F")
    if kind == ezc3d.ezc3d.FLOAT:
        return np.array(parameter.valuesAsDouble()).reshape(parameter.dimension(), order="F")
    if kind == ezc3d.ezc3d.CHAR:
        return list(parameter.valuesAsString())
    raise RuntimeError("Data type not recognized")


def _check_header(p: Path, raw: bytes) -> float | None:
    """InputError if the header's numbers cannot describe this file.

    Header words (16-bit, in the byte order of the processor type stored in
    the parameter section: 84 Intel, 85 DEC, 86 MIPS): 1 = first parameter
    block, 2 = points, 3 = analog samples per frame, 4/5 = first/last frame,
    7-8 = the point scale factor (a float; negative means 4-byte float data,
    else 2-byte integers scaled by it), 9 = first data block.  ezc3d reads the
    data by the header's scale and data block, so a zero or NaN scale or a data
    block inside the header gives numbers without meaning; and it quietly reads
    what there is of a truncated file, so the frame count is checked against
    the file size.  Returns the header's point scale factor (None when ezc3d is left to reject
    the file).
    """
    size = len(raw)
    head = raw[:512]
    if len(head) < 512 or head[1] != 0x50 or head[0] < 1:
        return None  # ezc3d rejects such a file
    param_info = raw[512 * (head[0] - 1) + 2 : 512 * (head[0] - 1) + 4]
    if len(param_info) < 2:
        raise InputError(f"{p}: not a readable C3D file (corrupt header: the parameters lie past the end of the file)")
    n_param_blocks, proc = param_info[0], param_info[1]
    order = ">" if proc == 86 else "<"  # 86: MIPS, big-endian
    words = struct.unpack(order + "12H", head[:24])
    n_points, n_analog, first, last, data_block = words[1], words[2], words[3], words[4], words[8]
    header_scale = _header_float(head[12:16], proc)
    if n_points and not (np.isfinite(header_scale) and header_scale != 0):
        raise InputError(
            f"{p}: not a readable C3D file (corrupt header: the point scale factor is {header_scale:g}; "
            "it must be a non-zero number)"
        )
    parameters_end = head[0] + max(1, n_param_blocks)
    if data_block < parameters_end or (data_block - 1) * 512 >= size:
        raise InputError(
            f"{p}: not a readable C3D file (corrupt header: the data start at block {data_block}, but the "
            f"parameters end at block {parameters_end - 1} and the file holds {(size + 511) // 512} blocks)"
        )
    if last == 0xFFFF or last < first:
        return header_scale  # frame count held elsewhere (long files)
    n_frames = last - first + 1
    bytes_per_value = 4 if header_scale < 0 else 2
    frame_bytes = (4 * n_points + n_analog) * bytes_per_value
    expected = (data_block - 1) * 512 + n_frames * frame_bytes
    if size < expected:
        have = max(0, size - (data_block - 1) * 512) // max(1, frame_bytes)
        raise InputError(f"{p}: truncated C3D file: the header announces {n_frames} frames, the file holds {have}")
    return header_scale


def _header_float(raw: bytes, proc: int) -> float:
    """A 4-byte float of the header in the processor's format (DEC: 16-bit halves swapped, 4x scaled)."""
    if proc == 85:
        if raw[1] & 0x7F == 0 and raw[0] & 0x80 == 0:  # exponent 0: zero (or DEC's reserved operand)
            return 0.0
        return struct.unpack("<f", raw[2:4] + raw[0:2])[0] / 4.0
    return struct.unpack(">f" if proc == 86 else "<f", raw)[0]


def _labels(point_group: dict, n_points: int) -> list[str]:
    """POINT:LABELS, LABELS2, ... cut to the number of points; blanks get a name."""
    labels: list[str] = []
    for key in ["LABELS"] + [f"LABELS{i}" for i in range(2, 100)]:
        if key not in point_group:
            break
        labels.extend(point_group[key]["value"])
    labels = [s.strip() for s in labels[:n_points]]
    labels += [""] * (n_points - len(labels))
    return [s or f"point{i + 1}" for i, s in enumerate(labels)]


def _unique(names: list[str]) -> list[str]:
    """Names made unique: a repeated label gets ``#2``, ``#3`` (MAC files repeat some)."""
    seen: dict[str, int] = {}
    out = []
    for n in names:
        k = seen.get(n, 0) + 1
        seen[n] = k
        out.append(n if k == 1 else f"{n}#{k}")
    return out


def _events(group: dict, start_s: float) -> list[tuple[str, str, float]]:
    """(side, kind, time_s) of the EVENT group's events (foot strikes and offs), on the recording's clock.

    ``EVENT:TIMES`` holds minutes and seconds from the capture's first frame (frame 0), so a trial
    whose points start at frame ``first_frame`` has its events ``first_frame / rate`` earlier.
    """
    try:
        used = int((_param(group, "USED") or [0])[0])
    except (TypeError, ValueError):
        return []
    times = group.get("TIMES", {}).get("value")
    if used <= 0 or times is None:
        return []
    times = np.asarray(times, dtype=float)
    if times.ndim != 2 or times.shape[0] < 2 or times.shape[1] < used:
        return []
    labels = [str(v) for v in (_param(group, "LABELS") or [])] + [""] * used
    contexts = [str(v) for v in (_param(group, "CONTEXTS") or [])] + [""] * used
    out = []
    for i in range(used):
        side, kind = gait_event(labels[i].strip(), contexts[i].strip())
        t = 60.0 * times[0, i] + times[1, i] - start_s
        if np.isfinite(t):
            out.append((side, kind, float(t)))
    return sorted(out, key=lambda e: e[2])


def _param(group: dict, name: str):
    entry = group.get(name)
    if not entry:
        return None
    value = entry.get("value")
    if value is None or len(value) == 0:
        return None
    return list(value)


def _first_line(exc: Exception) -> str:
    text = str(exc).strip().splitlines()
    return text[0] if text else type(exc).__name__
