#!/bin/bash
# Merges the tiles of tools/farm/slurm_render.sh into the whole image, as a job
# that depends on the array (docs/farm.md):
#
#   sbatch --dependency=afterok:$ARRAY_JOB --export=ALL,OUT=parts,IMAGE=image.exr \
#       tools/farm/slurm_merge.sh
#
# sturmray merge refuses parts that are missing, overlap, come from another
# scene or frame, or are unfinished, and names them.
#SBATCH --job-name=sturmray-merge
#SBATCH --output=sturmray-merge-%j.log
set -euo pipefail

OUT=${OUT:-parts}
IMAGE=${IMAGE:-image.exr}
STURMRAY=${STURMRAY:-sturmray}

shopt -s nullglob
parts=("$OUT"/part-*.exr)
if (( ${#parts[@]} == 0 )); then
    echo "slurm_merge.sh: no parts in $OUT" >&2
    exit 2
fi
exec "$STURMRAY" merge "$IMAGE" "${parts[@]}"
