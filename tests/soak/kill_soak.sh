#!/usr/bin/env bash
# Kill soak: `vifo run` on a fixed selection is killed with SIGKILL at random moments, resumed
# each time, and its results are compared with an uninterrupted run of the same selection.
#
#   tests/soak/kill_soak.sh                 # 20 kills (KILLS=30 SEED=7 VIFO=path OUT=dir to vary)
#
# SIGKILL cannot stop a single small write(2) half-way on a local disk, so a torn last line
# (what a kill during a results write leaves on other filesystems, or a full disk) is also
# made by hand: after every third kill the last line of the results file is cut in half.
# Resuming must then run that episode again and never read the half line as data.
# Prints the kills, the torn lines met, the episodes missing, duplicated or differing from
# the uninterrupted run, and whether the report tables are byte-identical; exits 1 unless
# all of those are 0 and the kills reached KILLS.
set -euo pipefail
cd "$(dirname "$0")/../.."

VIFO=${VIFO:-target/fast/vifo}
KILLS=${KILLS:-20}
SEED=${SEED:-1}
OUT=${OUT:-$(mktemp -d)}
[[ -x $VIFO ]] || { echo "kill_soak: $VIFO not found; build it: cargo build --profile fast -p vifo" >&2; exit 2; }
SELECTION=(--suite libero_spatial --per-family 2 --episodes 2 --policy zero --quiet)
RESULTS=results-zero.jsonl
RANDOM=$SEED

start=$(date +%s%N)
"$VIFO" run "${SELECTION[@]}" --out "$OUT/reference" > /dev/null
took_ms=$((($(date +%s%N) - start) / 1000000))
# Kill at a uniform moment in [0.3 s, max]: about twice the run time spread over the kills.
max_ms=$((2 * took_ms / KILLS)); ((max_ms < 600)) && max_ms=600
echo "uninterrupted run: $((took_ms / 1000)) s; kills at 0.3 s to $((max_ms / 1000)) s after each start"

kills=0 torn_seen=0 torn_made=0 runs=0
soak="$OUT/soak/$RESULTS"
while (( kills < KILLS )); do
  resume=(); [[ -e $soak ]] && resume=(--resume)
  "$VIFO" run "${SELECTION[@]}" "${resume[@]}" --out "$OUT/soak" > /dev/null 2>&1 &
  pid=$!
  runs=$((runs + 1))
  delay_ms=$((300 + (RANDOM * 32768 + RANDOM) % (max_ms - 300 + 1)))
  sleep "$(printf '%d.%03d' $((delay_ms / 1000)) $((delay_ms % 1000)))"
  if kill -KILL "$pid" 2>/dev/null; then
    wait "$pid" 2>/dev/null || true
    kills=$((kills + 1))
    if [[ -s $soak && $(tail -c 1 "$soak" | od -An -tx1 | tr -d ' ') != 0a ]]; then
      torn_seen=$((torn_seen + 1))
    elif [[ -s $soak ]] && (( kills % 3 == 0 )); then
      # Cut the last line in half: the episode it recorded was "never written".
      python3 - "$soak" <<'PY'
import sys
path = sys.argv[1]
data = open(path, "rb").read()
start = data.rfind(b"\n", 0, len(data) - 1) + 1
open(path, "r+b").truncate(start + (len(data) - start) // 2)
PY
      torn_made=$((torn_made + 1))
    fi
  else
    wait "$pid" || { echo "kill_soak: a run failed on its own" >&2; exit 1; }
    echo "kill_soak: the run finished before kill $((kills + 1)) (raise the run's size or lower KILLS)" >&2
    break
  fi
done
# The last resume runs to the end.
"$VIFO" run "${SELECTION[@]}" --resume --out "$OUT/soak" > /dev/null

python3 - "$OUT/reference/$RESULTS" "$soak" <<'PY' > "$OUT/compare.txt"
import json, sys
def load(path):
    records = [json.loads(l) for l in open(path, "rb").read().split(b"\n") if l.strip()]
    for r in records:
        r.pop("wall_ms", None)
    return records
def key(r):
    s = r["spec"]
    return (s["task"]["suite"], s["task"]["index"], s["protocol"], s["instance"], s["init"], s["episode"])
ref = {key(r): r for r in load(sys.argv[1])}
completed = {}
for r in load(sys.argv[2]):
    if r["outcome"]["status"] == "completed":
        completed.setdefault(key(r), []).append(r)
missing = sum(1 for k in ref if k not in completed)
duplicated = sum(len(v) - 1 for v in completed.values())
differing = sum(1 for k, v in completed.items() if k not in ref or v[0] != ref[k])
print(len(ref), missing, duplicated, differing)
PY
read -r episodes missing duplicated differing < "$OUT/compare.txt"
tables=identical
diff -r "$OUT/reference/report" "$OUT/soak/report" > /dev/null || tables=DIFFERENT

echo "kill soak: $runs runs, $kills SIGKILLs, torn last lines: $torn_seen met after a kill + $torn_made cut by hand"
echo "episodes: $episodes; missing $missing, duplicated $duplicated, differing $differing; report tables $tables ($OUT)"
(( kills >= KILLS && missing == 0 && duplicated == 0 && differing == 0 )) && [[ $tables == identical ]]
