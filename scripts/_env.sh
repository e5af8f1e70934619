# shellcheck shell=bash
# Shared set-up steps for scripts/run and scripts/test (source it, do not execute it).
# After sourcing, the working directory is the repository root.

cd "$(dirname "${BASH_SOURCE[0]}")/.." || exit

VENV=.venv
PY="$VENV/bin/python"

# Create .venv and install the pinned requirements; skipped while requirements.txt is unchanged.
ensure_venv() {
    if [[ ! -x "$PY" ]]; then
        echo "==> creating Python virtual environment in $VENV"
        python3 -m venv "$VENV"
    fi
    local stamp="$VENV/.req-stamp" want
    want="$(sha256sum requirements.txt | cut -d' ' -f1)"
    if [[ ! -f "$stamp" || "$(cat "$stamp")" != "$want" ]]; then
        echo "==> installing requirements.txt into $VENV"
        "$PY" -m pip install --quiet --disable-pip-version-check -r requirements.txt
        echo "$want" > "$stamp"
    fi
}

# Ecos (ecospy's C++ engine, libecosc.so) links against oneTBB's libtbb.so.12, which its wheel
# does not carry: install Debian's libtbb12 when the dynamic linker does not know it.
ensure_tbb() {
    if /sbin/ldconfig -p 2>/dev/null | grep -q 'libtbb\.so\.12 '; then
        return
    fi
    echo "==> installing libtbb12 (apt-get) for Ecos"
    local sudo=()
    [[ $(id -u) -eq 0 ]] || sudo=(sudo)
    if ! command -v apt-get >/dev/null 2>&1; then
        echo "error: Ecos needs libtbb.so.12 (oneTBB 2021); install it with your package manager" >&2
        return 1
    fi
    "${sudo[@]}" apt-get update -qq
    DEBIAN_FRONTEND=noninteractive "${sudo[@]}" apt-get install -y -qq libtbb12 >/dev/null
}

build_release() {
    echo "==> cargo build --release"
    cargo build --release
}

# The native master's Python bindings (master/python/, PyO3): maturin builds the wheel into dist/
# (one abi3 wheel, CPython >= 3.9) and it is installed into the venv, as a user's pip would.
build_bindings() {
    echo "==> maturin: the native master's Python bindings into dist/ and $VENV"
    rm -f dist/fmi_master-*.whl
    "$VENV/bin/maturin" build --release --quiet -m master/python/Cargo.toml --out dist
    "$PY" -m pip install --quiet --disable-pip-version-check --no-deps --force-reinstall dist/fmi_master-*.whl
}

package_fmus() {
    echo "==> packaging FMUs into dist/"
    "$PY" scripts/package.py
    "$PY" scripts/package_fmi3.py
    echo "==> packaging the SSP systems into dist/ssp/"
    "$PY" scripts/package_ssp.py
}

# Everything scripts/run installs: venv, libtbb12, release library and master, packaged FMUs and
# SSPs, the master's Python bindings.
setup_all() {
    ensure_venv
    ensure_tbb
    build_release
    package_fmus
    build_bindings
}
