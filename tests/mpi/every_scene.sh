#!/usr/bin/env bash
# Every shipped scene (scenes/*.toml and scenes/hard/*.toml) to END seconds on one rank and
# under `mpirun -np N`, compared by tests/mpi/compare_scene_runs.py; every scene is tried, and
# the script fails naming those that did not agree.
# Usage: every_scene.sh SPH PYTHON OUT_DIR N END [SCENE...]
set -uo pipefail
SPH=$1 PYTHON=$2 OUT=$3 N=$4 END=$5
shift 5
MPIRUN="mpirun --oversubscribe --allow-run-as-root"
mkdir -p "$OUT"
failed=()
scenes=("$@")
[ ${#scenes[@]} -gt 0 ] || scenes=(scenes/*.toml scenes/hard/*.toml)
for scene in "${scenes[@]}"; do
  name=$(basename "$(dirname "$scene")")_$(basename "$scene" .toml)
  if "$SPH" run "$scene" --end-time "$END" --out "$OUT/$name-1" >/dev/null 2>"$OUT/$name-1.err" \
    && timeout 600 $MPIRUN -np "$N" "$SPH" run "$scene" --end-time "$END" --out "$OUT/$name-$N" >/dev/null 2>"$OUT/$name-$N.err" \
    && "$PYTHON" tests/mpi/compare_scene_runs.py "$OUT/$name-1" "$OUT/$name-$N" "$N" "$name"; then
    :
  else
    failed+=("$name")
  fi
done
if [ ${#failed[@]} -gt 0 ]; then
  echo "scenes that did not agree on $N ranks: ${failed[*]}" >&2
  exit 1
fi
echo "every scene (${#scenes[@]}) on $N ranks agrees with one rank"
