#!/bin/bash
# One tile of a sturmray render as one task of a Slurm job array (docs/farm.md).
#
#   sbatch --array=0-$((TILES - 1)) --export=ALL,SCENE=scene.toml,TILES=$TILES,OUT=parts \
#       tools/farm/slurm_render.sh
#
# Task I renders band I of TILES into $OUT/part-I.exr with its film state
# beside it. A task that was stopped (a time limit sends SIGTERM: sturmray
# writes what it has and exits 130) continues from its state when requeued.
#SBATCH --job-name=sturmray-tile
#SBATCH --output=sturmray-tile-%A-%a.log
set -euo pipefail

: "${SCENE:?set SCENE to the scene file}"
: "${TILES:?set TILES to the number of tiles (the array is 0..TILES-1)}"
: "${SLURM_ARRAY_TASK_ID:?run as a Slurm array task (sbatch --array)}"
OUT=${OUT:-parts}
FRAME=${FRAME:-0}
STURMRAY=${STURMRAY:-sturmray}

mkdir -p "$OUT"
part="$OUT/part-$SLURM_ARRAY_TASK_ID.exr"
args=(render "$SCENE" --tile "$SLURM_ARRAY_TASK_ID/$TILES" --frame "$FRAME" -o "$part")
# As many threads as Slurm gave the task (all cores when it does not say).
if [[ -n "${SLURM_CPUS_PER_TASK:-}" ]]; then
    args+=(--threads "$SLURM_CPUS_PER_TASK")
fi
# A requeued task picks up where it stopped; a finished one has nothing left
# to do and rewrites the same image.
if [[ -f "${part%.exr}.state" ]]; then
    args+=(--resume)
fi
exec "$STURMRAY" "${args[@]}"
