#!/bin/bash
# `make test-farm`: docs/farm.md's recipes as users run them, on a real
# one-node Slurm cluster started here (tools/farm/local_cluster.sh) and with
# GNU parallel, on local job slots and over ssh to an sshd of our own:
#
#   tools/farm/test_cluster.sh STURMRAY [PYTHON]
#
# STURMRAY is the binary under test (the release build), PYTHON one with numpy
# and OpenEXR (.venv). Needs root (Slurm's daemons run as root here) and
# Debian's slurm-wlm, munge, parallel, openssh-server and rsync. Everything
# runs in a temporary folder, removed on success and kept (its path printed)
# on failure; the daemons are stopped either way.
set -euo pipefail

repo=$(cd "$(dirname "$0")/../.." && pwd)
farm=$repo/tools/farm
STURMRAY=$(realpath "${1:?usage: test_cluster.sh STURMRAY [PYTHON]}")
PYTHON=${2:-$repo/.venv/bin/python}
# Absolute, as the checks run in folders of their own; not resolved, as the
# venv's python is a link out of the venv.
[[ $PYTHON == /* ]] || PYTHON=$PWD/$PYTHON
export STURMRAY
if [[ $(id -u) != 0 ]]; then
    echo "test_cluster.sh: run as root: the test cluster's Slurm daemons run as root" >&2
    exit 2
fi

work=$(mktemp -d /tmp/sturmray-farm.XXXXXX)
chmod 755 "$work"
# shellcheck source=tools/farm/local_cluster.sh
source "$farm/local_cluster.sh"
sshd_pid=""
# parallel's own files (it keeps some in ~/.parallel) in the temporary folder.
export PARALLEL_HOME=$work/parallel-home
current="setup"

finish() {
    local status=$?
    cluster_stop
    [[ -z $sshd_pid ]] || { kill "$sshd_pid" 2>/dev/null && wait "$sshd_pid" 2>/dev/null || true; }
    if ((status == 0)); then
        rm -rf "$work"
    else
        echo "FAILED in $current; its files and the daemons' logs are in $work" >&2
    fi
}
trap finish EXIT
# Stopped from outside: exit, so that the EXIT trap stops the daemons.
trap 'exit 130' INT TERM

fail() {
    echo "FAIL $current: $*" >&2
    exit 1
}

check() {
    current=$1
    echo "--- $current"
}

passed() { echo "ok   $current (${SECONDS} s since the start)"; }

same_bytes() {
    cmp -s "$1" "$2" || fail "$1 and $2 differ: $3"
}

# Waits up to $1 seconds for the command after $2 (said in $2) to succeed.
wait_until() {
    local seconds=$1 what=$2
    shift 2
    cluster_wait "$seconds" "$@" || fail "not within $seconds s: $what"
}

# The value of field $2 of job $1 as scontrol shows it.
job_field() {
    scontrol --oneliner show job "$1" | head -n 1 | grep -oE "(^| )$2=[^ ]*" | cut -d= -f2
}

gone() { [[ -z $(squeue --noheader --jobs "$1" 2>/dev/null) ]]; }
rendering() { grep -q "photon map" "$1" 2>/dev/null; }

# Waits for merge job $1 (of array $2) to end; fails at once, with the
# report, when its array failed and it will never run.
wait_merge() {
    local merge=$1 array=$2
    merge_over() {
        gone "$merge" || [[ $(job_field "$merge" Reason) == DependencyNeverSatisfied ]]
    }
    wait_until 120 "the merge job ends" merge_over
    gone "$merge" || fail "the array failed: $("$farm/slurm_report.sh" "$array" "$merge")"
}

# A job that ran and ended well (scontrol keeps ended jobs for MinJobAge).
completed() {
    local state
    state=$(job_field "$1" JobState)
    [[ $state == COMPLETED ]] || fail "job $1 ended $state, not COMPLETED${2:+: $2}"
}

render() { "$STURMRAY" render "$@" >/dev/null 2>&1 || fail "sturmray render $*"; }

# The scenes: a path-traced glass ball over a mesh floor, its camera moving
# between frames 0 and 4; small, so each test takes seconds.
scenes=$work/scenes
mkdir -p "$scenes"
cat >"$scenes/square.obj" <<'EOF'
v -2 -2 0
v 2 -2 0
v 2 2 0
v -2 2 0
f 1 2 3 4
EOF
scene_text() { # $1: spp, $2: the ball's material
    cat <<EOF
[camera]
eye = [0, -3, 2]
look_at = [0, 0, 0]
fov = 45
width = 64
height = 48
[[camera.keys]]
frame = 0
eye = [0, -3, 2]
look_at = [0, 0, 0]
[[camera.keys]]
frame = 4
eye = [3, 0, 2]
look_at = [0, 0, 0]
[render]
spp = $1
integrator = "path"
[materials.paint]
type = "diffuse"
albedo = [0.6, 0.5, 0.4]
[materials.glass]
type = "dielectric"
[[objects]]
type = "mesh"
file = "square.obj"
material = "paint"
[[objects]]
type = "sphere"
radius = 0.4
material = "$2"
transform = { translate = [0, 0, 0.5] }
[[lights]]
type = "sphere"
center = [1, -1, 2]
radius = 0.2
radiance = [20, 20, 20]
EOF
}
scene_text 16 glass >"$scenes/s.toml"
# Long enough (seconds a tile on one thread) to be stopped midway.
slow_spp=1500
scene_text $slow_spp glass >"$scenes/slow.toml"

check "the cluster starts"
cluster_start "$work/cluster" || fail "see $work/cluster"
slurm_version=$(sinfo --version)
echo "$slurm_version, munge $(munged --version 2>&1 | head -n 1 | awk '{print $1}'), $(parallel --version | head -n 1)"
passed

check "an array of tiles and frames, then a dependent merge, gives the single-process images"
mkdir "$work/frames" && cd "$work/frames"
array=$(sbatch --parsable --array=0-5 --cpus-per-task=1 \
    --export=ALL,SCENE="$scenes/s.toml",TILES=3,FRAMES=0-1,OUT=parts "$farm/slurm_render.sh")
merge=$(sbatch --parsable --dependency=afterok:"$array" \
    --export=ALL,OUT=parts,FRAMES=0-1,IMAGE=frames/frame-%d.exr "$farm/slurm_merge.sh")
wait_until 10 "the merge job waits for the array" \
    eval '[[ $(job_field "$merge" Reason) == Dependency ]]'
wait_merge "$merge" "$array"
completed "$merge" "$(cat sturmray-merge-"$merge".log)"
for frame in 0 1; do
    render "$scenes/s.toml" --frame $frame -o whole-$frame.exr
    same_bytes frames/frame-$frame.exr whole-$frame.exr "frame $frame merged from 3 tiles, against one render"
done
cmp -s frames/frame-0.exr frames/frame-1.exr && fail "frames 0 and 1 are the same image: the camera did not move"
passed

check "a task cancelled mid-render resumes from its film state when requeued"
mkdir "$work/cancel" && cd "$work/cancel"
array=$(sbatch --parsable --array=0-1 --cpus-per-task=1 \
    --export=ALL,SCENE="$scenes/slow.toml",TILES=2,OUT=parts "$farm/slurm_render.sh")
merge=$(sbatch --parsable --dependency=afterok:"$array" \
    --export=ALL,OUT=parts,IMAGE=merged.exr "$farm/slurm_merge.sh")
log=sturmray-tile-$array-1.log
wait_until 60 "task 1 renders" rendering "$log"
# Its passes have begun (the photon pass is over); 1500 spp take seconds.
sleep 0.5
scancel "${array}_1"
wait_until 60 "the array ends" gone "$array"
[[ $(job_field "${array}_1" JobState) == CANCELLED ]] ||
    fail "task 1 is $(job_field "${array}_1" JobState), not CANCELLED"
stopped_at=$(grep -oE "film state parts/part-1.state \(64x24, [0-9]+ of $slow_spp spp" "$log" |
    grep -oE "[0-9]+ of" | cut -d' ' -f1) || fail "task 1 wrote no film state when cancelled: $(cat "$log")"
((stopped_at > 0 && stopped_at < slow_spp)) || fail "task 1 stopped after $stopped_at of $slow_spp samples"
echo "task 1 cancelled after $stopped_at of $slow_spp samples a pixel"
wait_until 30 "the merge job gives up on the array" \
    eval '[[ $(job_field "$merge" Reason) == DependencyNeverSatisfied ]]'
report=$("$farm/slurm_report.sh" "$array" "$merge") && fail "the report finds nothing wrong: $report"
echo "$report"
grep -qF "task 1 (frame 0, tile 1/2): CANCELLED" <<<"$report" || fail "the report does not name task 1"
grep -qF "scontrol requeue ${array}_1" <<<"$report" || fail "the report does not say how to requeue task 1"
# What the report says to do.
scontrol requeue "${array}_1"
scancel "$merge"
merge=$(sbatch --parsable --dependency=afterok:"${array}_1" \
    --export=ALL,OUT=parts,IMAGE=merged.exr "$farm/slurm_merge.sh")
wait_merge "$merge" "$array"
completed "$merge" "$(cat sturmray-merge-"$merge".log)"
grep -q "tile 1/2, run 2: .* --resume" "$log" || fail "the requeued task did not resume: $(cat "$log")"
render "$scenes/slow.toml" -o whole.exr
same_bytes merged.exr whole.exr "cancelled, requeued and merged, against one render"
passed

check "a task that fails (a bad scene for frame 1) keeps the merge from running, and the report names it"
mkdir "$work/failure" && cd "$work/failure"
cp "$scenes/s.toml" "$scenes/shot-0.toml"
sed 's/material = "glass"/material = "missing"/' "$scenes/s.toml" >"$scenes/shot-1.toml"
array=$(sbatch --parsable --array=0-3 --cpus-per-task=1 \
    --export=ALL,SCENE="$scenes/shot-%d.toml",TILES=2,FRAMES=0-1,OUT=parts "$farm/slurm_render.sh")
merge=$(sbatch --parsable --dependency=afterok:"$array" \
    --export=ALL,OUT=parts,FRAMES=0-1,IMAGE=frame-%d.exr "$farm/slurm_merge.sh")
wait_until 60 "the array ends" gone "$array"
wait_until 30 "the merge job gives up on the array" \
    eval '[[ $(job_field "$merge" Reason) == DependencyNeverSatisfied ]]'
[[ $(job_field "$merge" JobState) == PENDING && ! -e sturmray-merge-$merge.log ]] ||
    fail "the merge job ran: $(job_field "$merge" JobState)"
report=$("$farm/slurm_report.sh" "$array" "$merge") && fail "the report finds nothing wrong: $report"
echo "$report"
for tile in 0 1; do
    grep -qE "^task $((2 + tile)) \(frame 1, tile $tile/2\): FAILED, exit 2: sturmray: .*shot-1.toml" \
        <<<"$report" || fail "the report does not name frame 1, tile $tile and its scene"
done
grep -q "^4 tasks: 2 completed, 2 failed" <<<"$report" || fail "the report's count is wrong"
scancel "$merge"
passed

check "a node that dies mid-render: its tasks are requeued, finish when it is back, and merge"
mkdir "$work/node" && cd "$work/node"
array=$(sbatch --parsable --array=0-1 --cpus-per-task=1 --requeue \
    --export=ALL,SCENE="$scenes/slow.toml",TILES=2,OUT=parts "$farm/slurm_render.sh")
merge=$(sbatch --parsable --dependency=afterok:"$array" \
    --export=ALL,OUT=parts,IMAGE=merged.exr "$farm/slurm_merge.sh")
wait_until 60 "both tasks render" eval 'rendering sturmray-tile-$array-0.log && rendering sturmray-tile-$array-1.log'
node_kill
down_since=$SECONDS
wait_until 90 "the controller sees the node down" \
    eval '[[ $(sinfo --noheader --nodes=localhost --format=%T) == down* ]]'
echo "node down after $((SECONDS - down_since)) s"
for task in 0 1; do
    [[ $(job_field "${array}_$task" JobState) == PENDING && $(job_field "${array}_$task" Restarts) == 1 ]] ||
        fail "task $task is $(job_field "${array}_$task" JobState), not requeued"
done
node_start
wait_merge "$merge" "$array"
completed "$merge" "$(cat sturmray-merge-"$merge".log)"
for task in 0 1; do
    grep -q "tile $task/2, run 2: " sturmray-tile-"$array"-$task.log || fail "task $task did not run again"
done
same_bytes merged.exr "$work/cancel/whole.exr" "rendered across a node failure, against one render"
passed

check "parts with other seeds add up to the noise of one render with all their samples"
mkdir "$work/seeds" && cd "$work/seeds"
# A diffuse ball (no caustics, whose rare bright paths would make the noise
# figure itself noisy) and independent samples, whose parts add up to exactly
# the distribution of one render with all the samples.
scene_text 16 paint | sed 's/^\[render\]$/[render]\nsampler = "independent"/' >"$scenes/diffuse.toml"
passes=4
array=$(sbatch --parsable --array=0-$((passes - 1)) --cpus-per-task=1 \
    --export=ALL,SCENE="$scenes/diffuse.toml",OUT=passes "$farm/slurm_refine.sh")
merge=$(sbatch --parsable --dependency=afterok:"$array" \
    --export=ALL,OUT=passes,IMAGE=merged.exr "$farm/slurm_merge.sh")
render "$scenes/diffuse.toml" --spp $((16 * passes)) -o single.exr
sed 's/^\[render\]$/[render]\nseed = 1000/' "$scenes/diffuse.toml" >"$scenes/reference.toml"
render "$scenes/reference.toml" --spp 1024 -o reference.exr
wait_merge "$merge" "$array"
completed "$merge" "$(cat sturmray-merge-"$merge".log)"
for task in $(seq 0 $((passes - 1))); do
    grep -q "seed = $((1 + task))$" "$scenes/diffuse.seed-$((1 + task)).toml" ||
        fail "task $task's scene has no seed $((1 + task))"
done
noise=$("$PYTHON" "$farm/noise.py" reference.exr merged.exr single.exr passes/part-0.exr) ||
    fail "noise.py: $noise"
echo "$noise"
read -r _ merged_spp merged_rmse < <(sed -n 1p <<<"$noise")
read -r _ _ single_rmse < <(sed -n 2p <<<"$noise")
read -r _ _ part_rmse < <(sed -n 3p <<<"$noise")
[[ $merged_spp == $((16 * passes)) ]] || fail "the merged image holds $merged_spp spp, not $((16 * passes))"
# Ranges: over 12 seeds, the RMSE of one 64-spp render of this scene spread
# by 3% (sd) about its mean, so a ratio of two spreads by about 4.5%; the
# bounds are more than 3 of those from the expected 1 and 2 (sqrt(4)).
awk -v m="$merged_rmse" -v s="$single_rmse" 'BEGIN { exit !(m / s > 0.85 && m / s < 1.15) }' ||
    fail "the merged parts' RMSE is $merged_rmse, one render with all the samples has $single_rmse"
awk -v m="$merged_rmse" -v p="$part_rmse" 'BEGIN { exit !(p / m > 1.7 && p / m < 2.3) }' ||
    fail "one part's RMSE is $part_rmse, the merged image's $merged_rmse: not about twice"
passed

check "GNU parallel on local job slots, and slurm_render.sh under it"
mkdir "$work/parallel" && cd "$work/parallel"
seq 0 3 | parallel -j 2 "$STURMRAY" render "$scenes/s.toml" --tile {}/4 -o parts/part-{}.exr \
    --threads 1 2>parallel.log || fail "parallel: $(cat parallel.log)"
"$STURMRAY" merge merged.exr parts/part-*.exr 2>>parallel.log || fail "merge: $(cat parallel.log)"
same_bytes merged.exr "$work/frames/whole-0.exr" "4 tiles by parallel, against one render"
seq 0 3 | parallel -j 2 SLURM_ARRAY_TASK_ID={} SCENE="$scenes/s.toml" TILES=4 OUT=wrapped \
    "$farm/slurm_render.sh" 2>>parallel.log || fail "parallel slurm_render.sh: $(cat parallel.log)"
OUT=wrapped IMAGE=wrapped.exr "$farm/slurm_merge.sh" 2>>parallel.log || fail "slurm_merge.sh: $(cat parallel.log)"
same_bytes wrapped.exr "$work/frames/whole-0.exr" "slurm_render.sh under parallel, against one render"
passed

check "GNU parallel over ssh: a shared folder, and files sent and fetched back"
ssh_dir=$work/ssh
mkdir "$ssh_dir"
ssh-keygen -q -t ed25519 -N '' -f "$ssh_dir/host_key"
ssh-keygen -q -t ed25519 -N '' -f "$ssh_dir/id"
cp "$ssh_dir/id.pub" "$ssh_dir/authorized_keys"
ssh_port=${SSHD_PORT:-12222}
cat >"$ssh_dir/sshd_config" <<EOF
Port $ssh_port
ListenAddress 127.0.0.1
HostKey $ssh_dir/host_key
PidFile $ssh_dir/sshd.pid
AuthorizedKeysFile $ssh_dir/authorized_keys
AuthenticationMethods publickey
PasswordAuthentication no
KbdInteractiveAuthentication no
UsePAM no
# The keys live in a temporary folder under /tmp, which is world-writable.
StrictModes no
PermitRootLogin prohibit-password
AllowUsers $(id -un)
EOF
# sshd's privilege separation needs this folder (a system service would have it).
mkdir -p /run/sshd
/usr/sbin/sshd -D -e -f "$ssh_dir/sshd_config" 2>"$ssh_dir/sshd.log" &
sshd_pid=$!
echo "[127.0.0.1]:$ssh_port $(cut -d' ' -f1-2 "$ssh_dir/host_key.pub")" >"$ssh_dir/known_hosts"
ssh_command="ssh -p $ssh_port -i $ssh_dir/id -o IdentitiesOnly=yes -o BatchMode=yes \
-o UserKnownHostsFile=$ssh_dir/known_hosts"
host="$ssh_command $(id -un)@127.0.0.1"
sshd_answers() { $host true 2>/dev/null; }
wait_until 10 "sshd answers (its log: $ssh_dir/sshd.log)" sshd_answers

mkdir "$work/ssh-shared" && cd "$work/ssh-shared"
mkdir -p parts
seq 0 3 | parallel -S "2/$host" --workdir "$PWD" \
    "$STURMRAY" render "$scenes/s.toml" --tile {}/4 -o parts/part-{}.exr --threads 1 \
    2>parallel.log || fail "parallel -S: $(cat parallel.log)"
"$STURMRAY" merge merged.exr parts/part-*.exr 2>>parallel.log || fail "merge: $(cat parallel.log)"
same_bytes merged.exr "$work/frames/whole-0.exr" "4 tiles over ssh (shared folder), against one render"

# No shared folder: the scene folder goes to a folder of the remote's own and
# each part and its state come back (--workdir: there, not in the remote's
# home, so that the test writes nothing outside its temporary folder).
mkdir "$work/ssh-sent" && cd "$work/ssh-sent"
cp -r "$scenes" scenes
seq 0 3 | parallel -S "2/$host" --workdir "$work/remote" --transferfile scenes/ --cleanup \
    --return parts/part-{}.exr --return parts/part-{}.state --return parts/part-{}.png \
    "mkdir -p parts && $STURMRAY render scenes/s.toml --tile {}/4 -o parts/part-{}.exr --threads 1" \
    2>parallel.log || fail "parallel --transferfile: $(cat parallel.log)"
"$STURMRAY" merge merged.exr parts/part-*.exr 2>>parallel.log || fail "merge: $(cat parallel.log)"
same_bytes merged.exr "$work/frames/whole-0.exr" "4 tiles over ssh (files sent), against one render"
# --cleanup removes what came back, not the folder sent.
[[ -d $work/remote/scenes && -z $(find "$work/remote" -name 'part-*') ]] ||
    fail "--cleanup left parts on the remote: $(find "$work/remote" -name 'part-*')"
passed

echo "all farm checks passed on $slurm_version in $SECONDS s"
