#!/usr/bin/env bash
# Builds the distributable wheel and the sdist of sea-momentum into DIR ($1, default
# ${CARGO_TARGET_DIR:-target}/dist); the wheel's path is the last line printed.
#
# The wheel is abi3 (one file for CPython >= 3.9) and manylinux, and holds two builds of the
# extension, which sea_momentum chooses between at import (python/sea_momentum/_native_choice.py):
# - sea_momentum/_native.abi3.so: the architecture's baseline (x86-64: SSE2), runs on any CPU;
# - sea_momentum/_native_v3.abi3.so (x86-64 only): built for x86-64-v3 (AVX2, FMA, BMI2), used
#   where the CPU has them (every x86-64 of the last decade): the speed of a native build.
# Both override .cargo/config.toml's target-cpu=native through RUSTFLAGS: the workspace's own
# cargo builds, tests and benchmarks (and `pip install .`) stay native. They use the profile
# `wheel` (release without debug info) in the one target dir: target/wheel for the baseline,
# target/<host triple>/wheel for x86-64-v3 (--target keeps its flags off the build scripts), so
# neither rebuilds the other nor the native target/release. maturin builds each as a wheel (and
# checks its manylinux symbols); the x86-64-v3 wheel's extension is then added to the baseline
# wheel, its RECORD completed. The sdist carries no compiled file: `pip install` from it builds
# the baseline module only, for the building machine's architecture.
#
# The manylinux tag: with ziglang installed (pip install ziglang) both modules are linked by
# `zig cc` against glibc 2.17's symbols (maturin --zig), so the wheel is manylinux2014 and installs
# on any x86-64 Linux of the last decade (CentOS 7, Ubuntu 18.04 and later); without it they
# link against this machine's glibc and maturin tags the wheel with the newest glibc symbol
# they use (manylinux_2_35 on Debian 12). SEA_WHEEL_ZIG=0 skips zig even where it is installed.
#
# Needs maturin (pip install 'maturin>=1.5,<2') and Python 3.9 or later on PATH.
set -euo pipefail
cd "$(dirname "$0")/.."
target_dir="${CARGO_TARGET_DIR:-target}"
out="${1:-$target_dir/dist}"
python="${SEA_PYTHON:-python3}"
host=$(rustc -vV | sed -n 's/^host: //p')

linkage=()
if [[ ${SEA_WHEEL_ZIG:-1} != 0 ]] && "$python" -m ziglang version > /dev/null 2>&1; then
    linkage=(--zig --compatibility manylinux2014)
    echo "== linking with zig against glibc 2.17 (manylinux2014)"
else
    echo "== linking against this machine's glibc (no ziglang, or SEA_WHEEL_ZIG=0): the tag follows its symbols"
fi

mkdir -p "$out"
rm -f "$out"/sea_momentum-*.whl "$out"/sea_momentum-*.tar.gz
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT

echo "== the sdist (sources only)"
maturin sdist --out "$out"

if [[ $host == x86_64-* ]]; then
    echo "== the x86-64-v3 module ($host)"
    RUSTFLAGS="-C target-cpu=x86-64-v3" maturin build --profile wheel --target "$host" "${linkage[@]}" --out "$scratch/v3"
else
    echo "== $host: no x86-64-v3 module, the baseline only"
fi

echo "== the baseline module and its wheel"
RUSTFLAGS="" maturin build --profile wheel "${linkage[@]}" --out "$scratch/baseline"

echo "== the wheel: the baseline wheel with the x86-64-v3 module"
"$python" - "$scratch" "$out" <<'PYTHON'
import base64, hashlib, pathlib, sys, zipfile

scratch, out = pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2])
(baseline,) = (scratch / "baseline").glob("sea_momentum-*.whl")
added = {}
for v3_wheel in (scratch / "v3").glob("sea_momentum-*.whl"):
    with zipfile.ZipFile(v3_wheel) as archive:
        (name,) = [n for n in archive.namelist() if n.startswith("sea_momentum/_native.") and n.endswith(".so")]
        added[name.replace("/_native.", "/_native_v3.")] = archive.read(name)


def record_line(name: str, data: bytes) -> str:
    digest = base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()
    return f"{name},sha256={digest},{len(data)}\n"


with zipfile.ZipFile(baseline) as source, zipfile.ZipFile(out / baseline.name, "w", zipfile.ZIP_DEFLATED) as wheel:
    for info in source.infolist():
        data = source.read(info)
        if info.filename.endswith(".dist-info/RECORD"):
            # The added modules before the dist-info, RECORD last, as wheels are laid out.
            for name, module in added.items():
                entry = zipfile.ZipInfo(name, date_time=info.date_time)
                entry.external_attr = 0o755 << 16
                wheel.writestr(entry, module, zipfile.ZIP_DEFLATED)
            data += "".join(record_line(name, module) for name, module in added.items()).encode()
        wheel.writestr(info, data, zipfile.ZIP_DEFLATED)
PYTHON
ls "$out"/sea_momentum-*.whl
