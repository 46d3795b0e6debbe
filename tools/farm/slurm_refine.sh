#!/bin/bash
# More samples for one image, as a Slurm job array (docs/farm.md): every task
# renders the same region with a seed of its own, and slurm_merge.sh adds the
# parts up.
#
#   sbatch --array=0-$((N - 1)) --export=ALL,SCENE=scene.toml,OUT=passes \
#       tools/farm/slurm_refine.sh
#   sbatch --dependency=afterok:$ARRAY_JOB --export=ALL,OUT=passes,IMAGE=image.exr \
#       tools/farm/slurm_merge.sh
#
# Task I renders the whole image (or CROP=x0,y0,x1,y1) into $OUT/part-I.exr
# with seed FIRST_SEED + I (FIRST_SEED defaults to 1), with SPP samples a
# pixel if set, else the scene's. Each seed's scene is a copy of SCENE beside
# it, named scene.seed-S.toml (beside, so that its relative paths still
# resolve), with `seed = S` under [render]. The scene hash leaves the seed
# out, so the parts count as one scene. Stopped tasks resume when requeued.
#SBATCH --job-name=sturmray-refine
#SBATCH --output=sturmray-refine-%A-%a.log
#SBATCH --open-mode=append
set -euo pipefail

: "${SCENE:?set SCENE to the scene file (.toml)}"
: "${SLURM_ARRAY_TASK_ID:?run as a Slurm array task (sbatch --array)}"
OUT=${OUT:-passes}
STURMRAY=${STURMRAY:-sturmray}
task=$SLURM_ARRAY_TASK_ID
seed=$((${FIRST_SEED:-1} + task))

# The scene with `seed = S` as the first key of [render] and no other seed
# there (a [render] table is added when the scene has none), written whole
# under a temporary name and renamed, as a task running beside it may read it.
seeded="${SCENE%.toml}.seed-$seed.toml"
awk -v seed="$seed" '
    /^[[:space:]]*\[/ { table = $0; gsub(/[[:space:]]|#.*/, "", table) }
    table == "[render]" && /^[[:space:]]*seed[[:space:]]*=/ { next }
    { print }
    table == "[render]" && /^[[:space:]]*\[/ { print "seed = " seed; found = 1 }
    END { if (!found) print "[render]\nseed = " seed }
' "$SCENE" >"$seeded.$$"
mv "$seeded.$$" "$seeded"

# The threads and --resume as in slurm_render.sh: written again, not sourced,
# as sbatch runs a copy of each script away from its folder.
mkdir -p "$OUT"
part="$OUT/part-$task.exr"
args=(render "$seeded" -o "$part")
if [[ -n ${CROP:-} ]]; then
    args+=(--crop "$CROP")
else
    args+=(--tile 0/1)
fi
if [[ -n ${SPP:-} ]]; then
    args+=(--spp "$SPP")
fi
if [[ -n "${SLURM_CPUS_PER_TASK:-}" ]]; then
    args+=(--threads "$SLURM_CPUS_PER_TASK")
fi
if [[ -f "${part%.exr}.state" ]]; then
    args+=(--resume)
fi
echo "slurm_refine.sh: task $task, seed $seed," \
    "run $((${SLURM_RESTART_COUNT:-0} + 1)): $STURMRAY ${args[*]}" >&2
exec "$STURMRAY" "${args[@]}"
