#!/bin/bash
# Merges the tiles of tools/farm/slurm_render.sh into the whole image, as a job
# that depends on the array (docs/farm.md):
#
#   sbatch --dependency=afterok:$ARRAY_JOB --export=ALL,OUT=parts,IMAGE=image.exr \
#       tools/farm/slurm_merge.sh
#
# With FRAMES=A-B (as given to the array), each frame's tiles in
# $OUT/frame-F/ merge into its own image: IMAGE is then a printf pattern such
# as frame-%04d.exr. sturmray merge refuses parts that are missing, overlap,
# come from another scene or frame, or are unfinished, and names them.
#SBATCH --job-name=sturmray-merge
#SBATCH --output=sturmray-merge-%j.log
set -euo pipefail

OUT=${OUT:-parts}
IMAGE=${IMAGE:-image.exr}
STURMRAY=${STURMRAY:-sturmray}
shopt -s nullglob

# Merges the parts in folder $1 into image $2.
merge() {
    local parts=("$1"/part-*.exr)
    if ((${#parts[@]} == 0)); then
        echo "slurm_merge.sh: no parts in $1" >&2
        return 2
    fi
    mkdir -p "$(dirname "$2")"
    "$STURMRAY" merge "$2" "${parts[@]}"
}

if [[ -z ${FRAMES:-} ]]; then
    merge "$OUT" "$IMAGE"
    exit
fi
if [[ ! $FRAMES =~ ^([0-9]+)-([0-9]+)$ ]]; then
    echo "slurm_merge.sh: FRAMES=$FRAMES: expected FIRST-LAST, such as 0-99" >&2
    exit 2
fi
if [[ $IMAGE != *%* ]]; then
    echo "slurm_merge.sh: with FRAMES, IMAGE must hold the frame number's place, such as frame-%04d.exr" >&2
    exit 2
fi
failed=()
for ((frame = BASH_REMATCH[1]; frame <= BASH_REMATCH[2]; frame++)); do
    printf -v image -- "$IMAGE" "$frame"
    merge "$OUT/frame-$frame" "$image" || failed+=("$frame")
done
if ((${#failed[@]} > 0)); then
    echo "slurm_merge.sh: frames not merged: ${failed[*]}" >&2
    exit 2
fi
