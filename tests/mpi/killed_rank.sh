#!/usr/bin/env bash
# A split run whose rank 1 is killed (SIGKILL) after its first checkpoint: the job must fail
# with mpirun's report, and `sph run --resume` on the same ranks must complete the run from the
# last complete checkpoint. Usage: killed_rank.sh SPH OUT_DIR SCENE [ARGS...]
set -euo pipefail
SPH=$1 OUT=$2
shift 2
MPIRUN="mpirun --oversubscribe --allow-run-as-root"
$MPIRUN -np 2 "$SPH" run "$@" --checkpoint-every 10 --out "$OUT" >/dev/null 2>"$OUT.err" &
job=$!
for _ in $(seq 1200); do [ -f "$OUT/checkpoint.bin" ] && break; sleep 0.1; done
[ -f "$OUT/checkpoint.bin" ] || { echo "no checkpoint within 2 minutes" >&2; exit 1; }
killed=0
for pid in $(pgrep -f -- "--out $OUT" || true); do
  if tr '\0' '\n' <"/proc/$pid/environ" 2>/dev/null | grep -qx 'OMPI_COMM_WORLD_RANK=1'; then
    kill -9 "$pid" && killed=1
  fi
done
[ "$killed" = 1 ] || { echo "rank 1 was not found running" >&2; exit 1; }
if wait "$job"; then
  echo "expected the job to fail when a rank is killed" >&2; exit 1
fi
grep -q "signal 9" "$OUT.err" || { cat "$OUT.err" >&2; exit 1; }
timeout 600 $MPIRUN -np 2 "$SPH" run --resume "$OUT" >/dev/null
grep -q '"status": "completed"' "$OUT/summary.json"
echo "killed rank: the job failed, and --resume completed the run"
