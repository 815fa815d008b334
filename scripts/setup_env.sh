# Sourced by run_main.sh and run_tests.sh (from the repository root): creates the project
# virtual environment .venv once, activates it and installs sea-momentum with the extras of
# pyproject.toml that the caller names in SEA_EXTRAS (default `test`: everything the tests use;
# run_main.sh: `main`, what the main job uses). Works on a stock Python (PEP 668 refuses `pip
# install` into the system interpreter, so nothing is ever installed there). Uses uv when it is on
# PATH, else `python3 -m venv` and pip. SEA_PYTHON chooses the base interpreter (default python3).
#
# SEA_INSTALL chooses how the package is built:
# - `source` (default): `pip install .`; maturin builds the extension natively (.cargo/config.toml)
#   in release mode into target/ with the environment's interpreter as PYO3_PYTHON, so the cargo
#   commands that follow reuse the compiled crates;
# - `wheel`: the distributable wheel of scripts/build_wheel.sh (baseline and x86-64-v3 modules),
#   whose path is then in SEA_WHEEL.

venv_dir=.venv
base_python="${SEA_PYTHON:-python3}"

# Creates .venv with uv or the venv module; says what to install when neither works.
create_venv() {
    if [[ -x "$venv_dir/bin/python" ]]; then
        return
    fi
    echo "== creating the virtual environment $venv_dir (base: $(command -v "$base_python"))"
    if command -v uv > /dev/null; then
        uv venv --quiet --python "$(command -v "$base_python")" "$venv_dir"
    elif ! "$base_python" -m venv "$venv_dir"; then
        rm -rf "$venv_dir"
        echo "error: '$base_python -m venv' failed; install the venv module" \
            "(Debian/Ubuntu: apt-get install python3-venv) or uv, then run this again" >&2
        return 1
    fi
}

extras="${SEA_EXTRAS:-test}"
install_mode="${SEA_INSTALL:-source}"

# Runs pip (or uv's pip) in the environment, quietly.
pip_install() {
    if command -v uv > /dev/null; then
        uv pip install --quiet "$@"
    else
        python -m pip install --quiet --disable-pip-version-check "$@"
    fi
}

# Installs the package (release build) with the extras $extras.
install_package() {
    case "$install_mode" in
        source)
            echo "== installing sea-momentum[$extras] (release build for this CPU)"
            if command -v uv > /dev/null; then
                uv pip install --quiet --reinstall-package sea-momentum ".[$extras]"
            else
                pip_install ".[$extras]"
            fi
            ;;
        wheel)
            echo "== building the distributable wheel (scripts/build_wheel.sh)"
            pip_install "maturin>=1.5,<2" ziglang  # zig links against glibc 2.17: manylinux2014
            SEA_WHEEL=$(bash scripts/build_wheel.sh | tail -n 1)
            export SEA_WHEEL
            echo "== installing $SEA_WHEEL[$extras]"
            if command -v uv > /dev/null; then
                uv pip install --quiet --reinstall-package sea-momentum "$SEA_WHEEL[$extras]"
            else
                # The same version may be installed already: replace it by this build.
                pip_install --force-reinstall --no-deps "$SEA_WHEEL"
                pip_install "$SEA_WHEEL[$extras]"
            fi
            ;;
        *)
            echo "error: SEA_INSTALL='$install_mode' is not one of: source, wheel" >&2
            return 1
            ;;
    esac
}

# cargo test links sea_py against libpython (the wheel does not): the shared library must be
# there. Installs the Debian/Ubuntu package when it is missing and we are root (CI).
ensure_libpython() {
    local library
    library=$(python -c "import os, sysconfig; v = sysconfig.get_config_var; \
print(os.path.join(v('LIBDIR') or '', v('LDLIBRARY') or ''))")
    if [[ -e "$library" ]]; then
        return
    fi
    if [[ $(id -u) == 0 ]] && command -v apt-get > /dev/null; then
        echo "== $library is missing: installing python3-dev"
        # A fresh machine may have no package lists yet.
        apt-get update -q > /dev/null || true
        apt-get install -y -q python3-dev > /dev/null
    else
        echo "error: $library is missing: install the Python development package" \
            "(Debian/Ubuntu: python3-dev)" >&2
        return 1
    fi
}

create_venv
# shellcheck disable=SC1091
source "$venv_dir/bin/activate"
export PYO3_PYTHON="$PWD/$venv_dir/bin/python"
install_package

# Prints how to use the environment afterwards (the scripts' activation ends with them).
print_activation_hint() {
    echo "== to use this environment in your shell: source $venv_dir/bin/activate"
}
