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

build_release() {
    echo "==> cargo build --release"
    cargo build --release
}

package_fmus() {
    echo "==> packaging FMUs into dist/"
    "$PY" scripts/package.py
    "$PY" scripts/package_fmi3.py
}

# Everything scripts/run installs: venv, release library, packaged FMUs.
setup_all() {
    ensure_venv
    build_release
    package_fmus
}
