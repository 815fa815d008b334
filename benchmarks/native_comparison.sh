#!/usr/bin/env bash
# Side-by-side native benchmark: sea-momentum (`sea-sim bench`) against Pinocchio's C++
# (benchmarks/pinocchio_native.cpp), on the same machine, in the same run, alternating.
#
# usage: benchmarks/native_comparison.sh [--urdf PATH] [--joints a,b,c] [--runs N]
#                                        [--batches N] [--calls N] [--json FILE] [--rebuild]
#
#   --urdf PATH     model (default urdf/icub25.urdf); a free-flyer root is added on both sides
#   --joints LIST   keep only these joints (both sides; Pinocchio locks the others at 0)
#   --runs N        runs of each benchmark, alternating ours / Pinocchio (default 3)
#   --batches N     batches per operation, passed to both benchmarks (default: theirs, 31)
#   --calls N       calls per batch, passed to both benchmarks (default: theirs, 2000)
#   --json FILE     also write the table (and every run's figures) as JSON to FILE
#   --rebuild       recompile target/pinocchio_native even if it looks up to date
#
# Environment: PYTHON (default python3, else python) must be the interpreter where the pip
# package `pin` is installed; CXX (default g++); EXTRA_CXXFLAGS appended to the compile line.
#
# Each figure is, per run, the median over batches of the mean time per call (microseconds);
# the table shows the median over the runs, and ratio = ours / Pinocchio (< 1: ours faster).
set -euo pipefail

REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$REPO"

URDF="urdf/icub25.urdf"
JOINTS=""
RUNS=3
BATCHES=""
CALLS=""
JSON_OUT=""
REBUILD=0

usage() { sed -n '2,19p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'; }

while [[ $# -gt 0 ]]; do
  case "$1" in
    --urdf) URDF="${2:?--urdf needs a value}"; shift 2 ;;
    --joints) JOINTS="${2:?--joints needs a value}"; shift 2 ;;
    --runs) RUNS="${2:?--runs needs a value}"; shift 2 ;;
    --batches) BATCHES="${2:?--batches needs a value}"; shift 2 ;;
    --calls) CALLS="${2:?--calls needs a value}"; shift 2 ;;
    --json) JSON_OUT="${2:?--json needs a value}"; shift 2 ;;
    --rebuild) REBUILD=1; shift ;;
    -h|--help) usage; exit 0 ;;
    *) echo "native_comparison.sh: unknown argument '$1'" >&2; usage >&2; exit 2 ;;
  esac
done

[[ -f "$URDF" ]] || { echo "native_comparison.sh: no such URDF: $URDF" >&2; exit 2; }
[[ "$RUNS" =~ ^[1-9][0-9]*$ ]] || { echo "native_comparison.sh: --runs must be a positive integer" >&2; exit 2; }

if [[ -z "${PYTHON:-}" ]]; then
  if command -v python3 >/dev/null && python3 -c "import pinocchio" 2>/dev/null; then
    PYTHON=python3
  else
    PYTHON=python
  fi
fi
CXX="${CXX:-g++}"

# --- Pinocchio's installation (pip package `pin`, a cmeel prefix) ---------------------------
find_prefix() {
  "$PYTHON" - <<'EOF'
import os, site, subprocess, sys, sysconfig
candidates = []
try:
    out = subprocess.run([sys.executable, "-m", "cmeel", "cmake"], capture_output=True,
                         text=True, check=True).stdout
    candidates += [p for p in out.strip().split(os.pathsep) if p]
except Exception:
    pass
for base in [sysconfig.get_paths()["purelib"], sysconfig.get_paths()["platlib"],
             *site.getsitepackages()]:
    candidates.append(os.path.join(base, "cmeel.prefix"))
for prefix in candidates:
    if os.path.isfile(os.path.join(prefix, "include", "pinocchio", "config.hpp")):
        print(os.path.realpath(prefix))
        break
else:
    sys.exit("no cmeel prefix with include/pinocchio found (is the pip package `pin` installed?)")
EOF
}
PREFIX="$(find_prefix)"
INC="$PREFIX/include"
LIB="$PREFIX/lib"

# Build-time headers that `pin` does not pull in: Eigen and urdfdom_headers (header-only).
if [[ ! -f "$INC/eigen3/Eigen/Core" ]]; then
  echo "installing cmeel-eigen (Eigen headers) ..." >&2
  "$PYTHON" -m pip install -q cmeel-eigen
fi
if [[ ! -f "$INC/urdfdom_headers/urdf_model/model.h" ]]; then
  echo "installing cmeel-urdfdom-headers (urdf_model headers) ..." >&2
  "$PYTHON" -m pip install -q cmeel-urdfdom-headers
fi
[[ -f "$INC/eigen3/Eigen/Core" ]] || { echo "Eigen headers missing in $INC/eigen3" >&2; exit 1; }

# --- Compile the Pinocchio benchmark -----------------------------------------------------------
# Defines: those pinocchio's CMake targets export (Boost.MPL/Fusion limits, URDFDOM support).
# PINOCCHIO_ENABLE_TEMPLATE_INSTANTIATION is deliberately NOT defined, so the algorithms are
# instantiated in our translation unit with -O3 -march=native instead of being taken from the
# generic precompiled libpinocchio_default.so.
# ABI: the wheel's libraries are built for baseline x86-64 (Eigen alignment 16, plain malloc).
# With -march=native on an AVX/AVX-512 machine Eigen would otherwise use 32/64-byte alignment and
# its own aligned free(), which crashes when destroying the Model built by libpinocchio_parsers
# (free(): invalid pointer / SIGSEGV). EIGEN_MAX_ALIGN_BYTES=16 keeps the struct layouts, and
# EIGEN_MALLOC_ALREADY_ALIGNED=1 keeps the allocator, identical to the library's; the
# arithmetic is still vectorized with the native instruction set (unaligned loads).
BIN="target/pinocchio_native"
CXXFLAGS=(-O3 -march=native -DNDEBUG -std=c++17
  -DEIGEN_MAX_ALIGN_BYTES=16 -DEIGEN_MALLOC_ALREADY_ALIGNED=1
  -DBOOST_MPL_LIMIT_LIST_SIZE=30 -DBOOST_MPL_LIMIT_VECTOR_SIZE=30
  -DBOOST_MPL_CFG_NO_PREPROCESSED_HEADERS -DBOOST_FUSION_INVOKE_MAX_ARITY=12
  -DPINOCCHIO_WITH_URDFDOM -DPINOCCHIO_URDFDOM_HEADERS_MAJOR_VERSION=3
  -DPINOCCHIO_URDFDOM_HEADERS_MINOR_VERSION=0 -DPINOCCHIO_URDFDOM_HEADERS_PATCH_VERSION=0
  -I"$INC" -I"$INC/eigen3" -I"$INC/urdfdom_headers" -I"$INC/urdfdom"
  -Wno-stringop-overread)
# shellcheck disable=SC2206
CXXFLAGS+=(${EXTRA_CXXFLAGS:-})
LDFLAGS=(-L"$LIB" -Wl,-rpath,"$LIB" -lpinocchio_parsers -lpinocchio_default)
COMPILE=("$CXX" "${CXXFLAGS[@]}" benchmarks/pinocchio_native.cpp -o "$BIN" "${LDFLAGS[@]}")
STAMP="$BIN.cmdline"
mkdir -p target
if [[ $REBUILD -eq 1 || ! -x "$BIN" || benchmarks/pinocchio_native.cpp -nt "$BIN" \
      || ! -f "$STAMP" || "$(cat "$STAMP")" != "${COMPILE[*]}" ]]; then
  echo "compiling $BIN (about 1-2 minutes) ..." >&2
  "${COMPILE[@]}"
  printf '%s' "${COMPILE[*]}" > "$STAMP"
fi

# --- Our benchmark binary ----------------------------------------------------------------------
SEA_SIM="target/release/sea-sim"
if [[ ! -x "$SEA_SIM" ]]; then
  echo "building $SEA_SIM ..." >&2
  cargo build --release -p sea_ctrl
fi

# --- Runs, alternating -------------------------------------------------------------------------
COMMON=(--urdf "$URDF")
[[ -n "$JOINTS" ]] && COMMON+=(--joints "$JOINTS")
[[ -n "$BATCHES" ]] && COMMON+=(--batches "$BATCHES")
[[ -n "$CALLS" ]] && COMMON+=(--calls "$CALLS")

OUT_DIR="$(mktemp -d "${TMPDIR:-/tmp}/native_comparison.XXXXXX")"
trap 'rm -rf "$OUT_DIR"' EXIT
for ((i = 1; i <= RUNS; i++)); do
  echo "run $i/$RUNS: sea-sim ..." >&2
  "$SEA_SIM" bench "${COMMON[@]}" --json > "$OUT_DIR/ours_$i.json"
  echo "run $i/$RUNS: pinocchio_native ..." >&2
  "$BIN" "${COMMON[@]}" > "$OUT_DIR/pin_$i.json"
done

# --- Table ---------------------------------------------------------------------------------------
"$PYTHON" - "$OUT_DIR" "$RUNS" "$URDF" "$JOINTS" "$JSON_OUT" "${COMPILE[*]}" <<'EOF'
import json, os, platform, statistics, sys

out_dir, runs, urdf, joints, json_out, compile_cmd = sys.argv[1:7]
runs = int(runs)
ours = [json.load(open(os.path.join(out_dir, f"ours_{i}.json"))) for i in range(1, runs + 1)]
pins = [json.load(open(os.path.join(out_dir, f"pin_{i}.json"))) for i in range(1, runs + 1)]

# (label, our key, Pinocchio key)
rows = [
    ("rnea", "rnea_us", "rnea_us"),
    ("crba", "crba_us", "crba_us"),
    ("centroidal_momentum_matrix", "centroidal_momentum_matrix_us", "centroidal_momentum_matrix_us"),
    ("  vs pin ccrba (Ag + hg + Ig)", "centroidal_momentum_matrix_us", "ccrba_us"),
    ("frame_jacobian", "frame_jacobian_us", "frame_jacobian_us"),
    ("frame_jacobian_dot_v", "frame_jacobian_dot_v_us", "frame_jacobian_dot_v_us"),
]

def med(runs_, key):
    values = [r[key] for r in runs_ if key in r]
    return statistics.median(values) if values else None

warnings = []
if ours[0].get("nv") != pins[0].get("nv"):
    warnings.append(f"nv differs: ours {ours[0].get('nv')}, Pinocchio {pins[0].get('nv')}")
if ours[0].get("frame") != pins[0].get("frame"):
    warnings.append(f"frame differs: ours {ours[0].get('frame')}, Pinocchio {pins[0].get('frame')}")

table = []
for label, ok, pk in rows:
    o, p = med(ours, ok), med(pins, pk)
    table.append({"operation": label.strip(), "ours_key": ok, "pinocchio_key": pk,
                  "ours_us": o, "pinocchio_us": p,
                  "ratio": (o / p) if (o is not None and p) else None,
                  "ours_runs_us": [r.get(ok) for r in ours],
                  "pinocchio_runs_us": [r.get(pk) for r in pins]})

def fmt(x, spec):
    return format(x, spec) if x is not None else "-"

print()
print(f"{urdf}" + (f" (joints: {joints})" if joints else "")
      + f", nv = {pins[0].get('nv')}, frame {pins[0].get('frame')}; "
      + f"median of {runs} alternating runs, microseconds per call")
print(f"Pinocchio {pins[0].get('pinocchio_version')} C++ (Eigen {pins[0].get('eigen_version')}, "
      f"{pins[0].get('simd')}), -O3 -march=native")
print()
header = f"{'operation':<32} {'ours':>9} {'pinocchio':>10} {'ours/pin':>9}"
print(header)
print("-" * len(header))
for row, (label, _, _) in zip(table, rows):
    print(f"{label:<32} {fmt(row['ours_us'], '9.3f')} {fmt(row['pinocchio_us'], '10.3f')} "
          f"{fmt(row['ratio'], '9.2f')}")
print()
print("notes: pinocchio crba fills only the upper triangle of M; pinocchio frame_jacobian is "
      "computeFrameJacobian (LOCAL_WORLD_ALIGNED, forward kinematics included); "
      "frame_jacobian_dot_v is forwardKinematics(q, v, 0) + getFrameClassicalAcceleration.")
for w in warnings:
    print("WARNING:", w)

if json_out:
    doc = {
        "urdf": urdf, "joints": joints or None, "runs": runs,
        "nv": pins[0].get("nv"), "frame": pins[0].get("frame"),
        "machine": {"platform": platform.platform(), "processor": platform.processor(),
                    "cpus": os.cpu_count()},
        "pinocchio_compile": compile_cmd,
        "pinocchio_version": pins[0].get("pinocchio_version"),
        "eigen_version": pins[0].get("eigen_version"), "simd": pins[0].get("simd"),
        "table": table, "warnings": warnings,
        "notes": pins[0].get("notes"),
        "ours_runs": ours, "pinocchio_runs": pins,
    }
    os.makedirs(os.path.dirname(os.path.abspath(json_out)), exist_ok=True)
    with open(json_out, "w") as f:
        json.dump(doc, f, indent=2)
    print(f"wrote {json_out}")
EOF
