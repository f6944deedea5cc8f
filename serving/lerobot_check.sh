#!/usr/bin/env bash
# Runs LIBERO episodes through upstream LeRobot's own async inference server (the path MolmoAct2
# is served on), with a randomly initialised ACT policy standing in for the model: the pickled
# RemotePolicyConfig and TimedObservation, the streamed observation and the TimedAction chunks
# all go through LeRobot's real code. Prints the run's summary and exits non-zero on any error.
# Usage: serving/lerobot_check.sh [VENV_DIR]   (default ~/.cache/libero-vifo/lerobot-venv)
# The venv is built from PyPI once (lerobot[async]==0.4.4 with torch: about 8.5 GB) and reused.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(dirname "$here")"
venv="${1:-${HOME}/.cache/libero-vifo/lerobot-venv}"
py="${PYTHON:-python3}"
die() { echo "lerobot_check: $*" >&2; exit 1; }

if [ ! -f "$venv/.complete" ]; then
  echo "== creating $venv (LeRobot 0.4.4 and torch from PyPI; one-off, several minutes)"
  "$py" -m venv "$venv" || die "could not create a virtualenv at $venv"
  "$venv/bin/python" -m pip install --disable-pip-version-check -q "lerobot[async]==0.4.4" \
    || die "pip could not install lerobot[async]==0.4.4 (see pip's message above)"
  touch "$venv/.complete"
fi
# The release build, as users run it; cargo rebuilds only what changed.
vifo="${VIFO:-$root/target/release/vifo}"
if [ -z "${VIFO:-}" ]; then
  (cd "$root" && cargo build --release -q -p vifo) || die "could not build vifo"
fi
[ -x "$vifo" ] || die "no vifo program at $vifo"
work="$(mktemp -d)"
server_pid=""
trap '[ -n "$server_pid" ] && kill "$server_pid" 2>/dev/null; rm -rf "$work"' EXIT
"$venv/bin/python" "$here/lerobot_stand_in.py" "$work/policy" 256 || die "could not make the stand-in policy"
port=$("$py" -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
# From the scratch folder: the server writes a logs/ folder where it starts.
(cd "$work" && exec "$venv/bin/python" -m lerobot.async_inference.policy_server --host=127.0.0.1 --port="$port" --fps=30) \
  > "$work/server.log" 2>&1 &
server_pid=$!
for _ in $(seq 100); do
  grep -q "PolicyServer started" "$work/server.log" && break
  kill -0 "$server_pid" 2>/dev/null || { cat "$work/server.log"; die "the LeRobot server exited"; }
  sleep 0.3
done
url="grpc://127.0.0.1:$port?policy_type=act&pretrained=$work/policy&device=cpu"
status=0
"$vifo" run --quiet --suite libero_goal --protocol original --episodes 1 --policy "$url" \
  --model-profile molmoact2 --size 256 --out "$work/run" | grep -v '^|' || status=$?
errors=$(grep -ci "error" "$work/server.log" || true)
echo "LeRobot server: $(grep -c 'Action chunk #' "$work/server.log" || true) action chunks sent, $errors error lines in its log"
[ "$status" = 0 ] && [ "$errors" = 0 ] || { tail -20 "$work/server.log"; die "episodes ended in errors (above)"; }
echo "lerobot_check: every episode ran through LeRobot's own server"
