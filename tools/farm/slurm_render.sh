#!/bin/bash
# One tile of a sturmray render as one task of a Slurm job array (docs/farm.md).
#
#   sbatch --array=0-$((TILES - 1)) --export=ALL,SCENE=scene.toml,TILES=$TILES,OUT=parts \
#       tools/farm/slurm_render.sh
#
# Task I renders band I of TILES into $OUT/part-I.exr with its film state
# beside it. With FRAMES=A-B the array covers every tile of every frame
# (--array=0-$((TILES * (B - A + 1) - 1))): task I renders tile I % TILES of
# frame A + I / TILES into $OUT/frame-F/part-T.exr. SCENE may name one scene
# per frame with a printf pattern (shot-%04d.toml); without one, --frame picks
# the frame of the scene's camera path.
#
# A task that was stopped (a time limit or scancel sends SIGTERM: sturmray
# writes what it has and exits 130) continues from its state when requeued.
# Each run says what it renders on the first line it logs, which
# tools/farm/slurm_report.sh reads; the log is appended to, so a requeued
# task's earlier runs stay in it.
#SBATCH --job-name=sturmray-tile
#SBATCH --output=sturmray-tile-%A-%a.log
#SBATCH --open-mode=append
set -euo pipefail

: "${SCENE:?set SCENE to the scene file}"
: "${TILES:?set TILES to the number of tiles}"
: "${SLURM_ARRAY_TASK_ID:?run as a Slurm array task (sbatch --array)}"
OUT=${OUT:-parts}
STURMRAY=${STURMRAY:-sturmray}
task=$SLURM_ARRAY_TASK_ID

if [[ -n ${FRAMES:-} ]]; then
    if [[ ! $FRAMES =~ ^([0-9]+)-([0-9]+)$ ]] || ((BASH_REMATCH[1] > BASH_REMATCH[2])); then
        echo "slurm_render.sh: FRAMES=$FRAMES: expected FIRST-LAST, such as 0-99" >&2
        exit 2
    fi
    frame=$((BASH_REMATCH[1] + task / TILES))
    tile=$((task % TILES))
    if ((frame > BASH_REMATCH[2])); then
        echo "slurm_render.sh: task $task is past the last frame of $FRAMES ($TILES tiles each)" >&2
        exit 2
    fi
    dir=$OUT/frame-$frame
else
    frame=${FRAME:-0}
    tile=$task
    dir=$OUT
fi
scene=$SCENE
if [[ $SCENE == *%* ]]; then
    printf -v scene -- "$SCENE" "$frame"
fi

mkdir -p "$dir"
part="$dir/part-$tile.exr"
args=(render "$scene" --tile "$tile/$TILES" --frame "$frame" -o "$part")
# As many threads as Slurm gave the task (all cores when it does not say).
if [[ -n "${SLURM_CPUS_PER_TASK:-}" ]]; then
    args+=(--threads "$SLURM_CPUS_PER_TASK")
fi
# A requeued task picks up where it stopped; a finished one has nothing left
# to do and rewrites the same image.
if [[ -f "${part%.exr}.state" ]]; then
    args+=(--resume)
fi
echo "slurm_render.sh: task $task, frame $frame, tile $tile/$TILES," \
    "run $((${SLURM_RESTART_COUNT:-0} + 1)): $STURMRAY ${args[*]}" >&2
exec "$STURMRAY" "${args[@]}"
