"""The C++ side: the GoogleTest suite (under ASan/UBSan, and optimised for this machine) and an installed
find_package(yoyogait)."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
BUILD = ROOT / "build" / "pytest"


def _cmake() -> str:
    exe = shutil.which("cmake") or str(Path(sys.executable).parent / "cmake")
    if not Path(exe).exists() and not shutil.which(exe):
        pytest.fail("cmake is needed to build the C++ tests (pip install '.[test]' brings it)")
    return exe


def _generator() -> list[str]:
    return ["-G", "Ninja"] if shutil.which("ninja") else []


def _run(cmd, **kw) -> subprocess.CompletedProcess:
    proc = subprocess.run(cmd, capture_output=True, text=True, **kw)
    if proc.returncode != 0:
        pytest.fail(f"{' '.join(map(str, cmd))} failed:\n{proc.stdout[-4000:]}\n{proc.stderr[-4000:]}")
    return proc


# The two builds of the suite: checked under the sanitizers, and optimised for this machine (FMA and
# all), where the bit-for-bit guarantees (step == run, the SSE2 pair step == the scalar step) must
# hold as well; yoyogait::yoyogait brings the flags they need. The sanitizer build compiles the test
# files as one unit: instrumenting the shared headers and GoogleTest once instead of once per file
# halves its build time.
SUITE_BUILDS = {
    "debug-sanitizers": [
        "-DCMAKE_BUILD_TYPE=Debug",
        "-DCMAKE_UNITY_BUILD=ON",
        "-DCMAKE_CXX_FLAGS=-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer",
    ],
    "release-native": [
        "-DCMAKE_BUILD_TYPE=Release",
        "-DCMAKE_CXX_FLAGS_RELEASE=-O3 -DNDEBUG",
        "-DYOYOGAIT_TESTS_MARCH_NATIVE=ON",
    ],
}


@pytest.mark.parametrize("build_name", list(SUITE_BUILDS))
def test_googletest_suite_passes(build_name):
    """Every GoogleTest case of tests/cpp passes in a Debug build under ASan/UBSan and in a Release
    build with -O3 -march=native (where the compiler has it)."""
    cmake = _cmake()
    build = BUILD / f"gtest-{build_name}"
    configure = _run(
        [cmake, "-S", ROOT, "-B", build, *_generator(), "-DYOYOGAIT_BUILD_TESTS=ON", *SUITE_BUILDS[build_name]]
    )
    _run([cmake, "--build", build, "--parallel", str(min(os.cpu_count() or 2, 2))])
    exe = next(build.rglob("yoyogait_tests"))
    proc = _run([exe, "--gtest_brief=0"], env={**os.environ, "ASAN_OPTIONS": "detect_leaks=1"})
    ran = re.search(r"\[==========\] (\d+) tests? from", proc.stdout)
    passed = re.search(r"\[  PASSED  \] (\d+) tests?", proc.stdout)
    assert ran and passed and int(passed.group(1)) == int(ran.group(1)) >= 20, proc.stdout[-2000:]
    native = re.search(r"yoyogait_tests: (.*)", configure.stdout)
    print(f"GoogleTest ({build_name}{', ' + native.group(1) if native else ''}): {passed.group(1)} C++ tests passed")


def test_installed_package_is_found_by_find_package(tmp_path):
    """cmake --install gives a prefix where find_package(yoyogait) builds and runs examples/cpp (the marker
    and the IMU paths), with the compile options of yoyogait::yoyogait (-ffp-contract=off)."""
    cmake = _cmake()
    build = BUILD / "install"
    prefix = tmp_path / "prefix"
    _run([cmake, "-S", ROOT, "-B", build, *_generator(), f"-DCMAKE_INSTALL_PREFIX={prefix}"])
    _run([cmake, "--install", build])
    assert (prefix / "include" / "yoyogait" / "estimator.hpp").is_file()
    example = tmp_path / "example"
    _run(
        [
            cmake,
            "-S",
            ROOT / "examples" / "cpp",
            "-B",
            example,
            *_generator(),
            f"-DCMAKE_PREFIX_PATH={prefix}",
            "-DCMAKE_BUILD_TYPE=Release",
            "-DCMAKE_EXPORT_COMPILE_COMMANDS=ON",
        ]
    )
    _run([cmake, "--build", example])
    # The flag the bit-for-bit guarantees need comes with the installed target.
    compiler = next(example.glob("CMakeFiles/*/CMakeCXXCompiler.cmake")).read_text()
    if re.search(r'set\(CMAKE_CXX_COMPILER_ID "(GNU|Clang|AppleClang)"\)', compiler):
        commands = (example / "compile_commands.json").read_text()
        assert "-ffp-contract=off" in commands, commands
    out = _run([next(example.rglob("walk_estimate"))]).stdout
    f = float(re.search(r"step_frequency_hz=([-\d.]+)", out).group(1))
    R = float(re.search(r"R_m=([-\d.]+)", out).group(1))
    assert abs(f - 1.8) < 0.018 and abs(R - 0.115) < 0.006, out
    _feed_online_stdin(next(example.rglob("online_stdin")))
    _feed_imu_stdin(next(example.rglob("imu_stdin")))


def _feed_online_stdin(exe):
    """examples/cpp/online_stdin answers each CSV frame with one estimate line, finds the walk's cadence and
    says when it may be used (valid, and why not before); frames separated by spaces read the same."""
    import math

    lines = ["t_s,LASI_x,LASI_y,LASI_z,RASI_x,RASI_y,RASI_z"]
    n = 800  # 8 s at 100 Hz, a Yoyo walk at 1.8 steps/s and 1.2 m/s, millimetres, y up
    for k in range(n):
        t = k / 100.0
        th = 2 * math.pi * 1.8 * t
        x, y = 1200 * t - 12 * math.sin(th), 1000 + 12 * math.cos(th)
        left = "nan,nan,nan" if k % 50 == 7 else f"{x:.3f},{y:.3f},-125"
        lines.append(f"{t:.2f},{left},{x:.3f},{y:.3f},125")
    proc = subprocess.run([str(exe), "y", "0.001"], input="\n".join(lines) + "\n", capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    rows = proc.stdout.strip().splitlines()
    assert rows[0].startswith("t_s,vx_mps,vz_mps") and len(rows) == n + 1
    last = dict(zip(rows[0].split(","), rows[-1].split(",")))
    assert abs(float(last["step_frequency_hz"]) - 1.8) < 0.05 and abs(float(last["speed_mps"]) - 1.2) < 0.05, last
    assert last["walking"] == "1" and last["status"] == "0"
    assert last["valid"] == "1" and last["invalid_reason"] == "0"
    first = dict(zip(rows[0].split(","), rows[1].split(",")))
    assert first["valid"] == "0" and int(first["invalid_reason"]) & 1  # acquiring
    # Separated by spaces instead of commas (a missing coordinate as "nan"): the same estimates.
    spaced = [line.replace(",", " ") for line in lines]
    same = subprocess.run([str(exe), "y", "0.001"], input="\n".join(spaced) + "\n", capture_output=True, text=True)
    assert same.returncode == 0 and same.stdout == proc.stdout, same.stderr


def _feed_imu_stdin(exe):
    """examples/cpp/imu_stdin answers each IMU sample with one line of every ImuEstimate field, finds a
    SYNTHETIC walk's cadence and speed and says when they may be used; a sample of the wrong width is
    one line on stderr and exit 2; samples separated by spaces or tabs read the same; lines that are not
    numbers are skipped with one note on stderr."""
    from yoyogait.estimators.imu import IMU_ESTIMATE_FIELDS
    from yoyogait.synthetic_imu import make_imu_walk

    walk = make_imu_walk(duration_s=12.0)
    rec = walk.recording
    lines = ["t_s,ax,ay,az,gx,gy,gz"] + [
        ",".join(f"{v:.9g}" for v in (t, *a, *g)) for t, a, g in zip(rec.time_s, rec.acc_mps2, rec.gyr_rad_s)
    ]
    proc = subprocess.run(
        [str(exe), f"{rec.sensor_height_m:.6f}"], input="\n".join(lines) + "\n", capture_output=True, text=True
    )
    assert proc.returncode == 0, proc.stderr
    rows = proc.stdout.strip().splitlines()
    assert rows[0].split(",") == [name for name, _, _ in IMU_ESTIMATE_FIELDS] and len(rows) == rec.time_s.size + 1
    last = dict(zip(rows[0].split(","), rows[-1].split(",")))
    assert abs(float(last["step_frequency_hz"]) - walk.truth.step_frequency_hz[-1]) < 0.02, last
    assert abs(float(last["speed_mps"]) - walk.truth.speed_mps[-1]) < 0.05, last
    assert last["valid"] == "1" and last["reason"] == "0" and last["walking"] == "1"
    first = dict(zip(rows[0].split(","), rows[1].split(",")))
    assert first["valid"] == "0" and first["reason"] == "6"  # ImuReason::kAcquiring
    bad = subprocess.run([str(exe)], input="0,0,0,9.81\n", capture_output=True, text=True)
    assert bad.returncode == 2 and len(bad.stderr.strip().splitlines()) == 1 and "got 4 cells" in bad.stderr
    # The same samples separated by spaces and tabs (as sensor streams print them): the same estimates.
    spaced = [line.replace(",", " " if k % 2 else "\t") for k, line in enumerate(lines)]
    same = subprocess.run(
        [str(exe), f"{rec.sensor_height_m:.6f}"], input="\n".join(spaced) + "\n", capture_output=True, text=True
    )
    assert same.returncode == 0 and same.stdout == proc.stdout, same.stderr
    # Lines that are not numbers pass with one note on stderr, not in silence (the first may be a header).
    words = subprocess.run(
        [str(exe)], input="time acc gyr\nt ax ay az gx gy gz\nmore words\n", capture_output=True, text=True
    )
    assert words.returncode == 0 and words.stderr.count("skipping lines that are not numbers") == 1, words.stderr
    assert "t ax ay az" in words.stderr
    # A clock from an epoch keeps its samples apart to the microsecond in the time column.
    epoch = [
        ",".join(f"{v:.6f}" for v in (1.7e9 + t, *a, *g)) for t, a, g in zip(rec.time_s, rec.acc_mps2, rec.gyr_rad_s)
    ]
    late = subprocess.run([str(exe)], input="\n".join(epoch[:5]) + "\n", capture_output=True, text=True)
    times = [float(row.split(",")[0]) for row in late.stdout.strip().splitlines()[1:]]
    assert late.returncode == 0 and [round(t - 1.7e9, 6) for t in times] == [round(t, 6) for t in rec.time_s[:5]]
