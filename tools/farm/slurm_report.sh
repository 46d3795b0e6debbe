#!/bin/bash
# What became of the tasks of a job array of tools/farm/slurm_render.sh (or
# slurm_refine.sh), and what to do about those that did not finish:
#
#   tools/farm/slurm_report.sh ARRAY_JOB [MERGE_JOB]
#
# Prints one line per task that failed, was cancelled or timed out: its frame
# and tile, its state and exit code, and the error its log ends with. Then,
# if there are such tasks, the commands that requeue them (they resume from
# their film states) and submit the merge again: a merge job that waits with
# --dependency=afterok on an array whose task failed never runs
# (DependencyNeverSatisfied), even after the task is requeued and succeeds.
#
# Exit status: 0 when every task completed, 1 when some failed, 3 when none
# failed but some are still pending or running, 2 for a job Slurm does not
# know (it forgets finished jobs after MinJobAge, 300 s by default; sacct
# keeps them on clusters with accounting).
set -euo pipefail

array=${1:?usage: slurm_report.sh ARRAY_JOB [MERGE_JOB]}
merge=${2:-}
if ! records=$(scontrol --oneliner show job "$array" 2>&1); then
    echo "slurm_report.sh: $records" >&2
    exit 2
fi
# In task order (scontrol lists the last first).
records=$(awk 'match($0, /ArrayTaskId=[0-9]+/) { print substr($0, RSTART + 12, RLENGTH - 12) "\t" $0 }' \
    <<<"$records" | sort -n | cut -f2-)

# The value of field $1 in the record $2 (values without spaces only).
field() { [[ " $2 " =~ \ $1=([^ ]*)\  ]] && echo "${BASH_REMATCH[1]}"; }

failed=() completed=0 waiting=0
while IFS= read -r record; do
    [[ -n $record ]] || continue
    id=$(field ArrayTaskId "$record") state=$(field JobState "$record")
    case $state in
    COMPLETED) completed=$((completed + 1)) ;;
    PENDING | RUNNING | CONFIGURING | COMPLETING | REQUEUED | RESIZING | SUSPENDED)
        waiting=$((waiting + 1)) ;;
    *)
        failed+=("$id")
        log=$(field StdOut "$record")
        what="" error=""
        if [[ -r $log ]]; then
            # What the last run rendered (its first line), and the last word
            # of sturmray or Slurm about it: an error, or the film state
            # written when it was stopped.
            what=$(awk -F': ' '/^slurm_(render|refine)\.sh: task / {w = $2} END {print w}' "$log" |
                sed 's/^task [0-9]*, //; s/, run [0-9]*$//')
            error=$(awk '/^slurm_(render|refine)\.sh: task / {e = ""}
                /^sturmray: |error:|film state/ {e = $0} END {print e}' "$log")
        fi
        echo "task $id${what:+ ($what)}: $state, exit $(field ExitCode "$record" | cut -d: -f1)${error:+: $error}"
        echo "    log: ${log:-none}"
        ;;
    esac
done <<<"$records"

echo "$((completed + waiting + ${#failed[@]})) tasks: $completed completed, ${#failed[@]} failed," \
    "$waiting pending or running"
if ((${#failed[@]} > 0 && waiting > 0)); then
    echo "Report again when no task is pending or running, for the commands that requeue them."
    exit 1
fi
if ((${#failed[@]} > 0)); then
    tasks=$(printf "${array}_%s," "${failed[@]}")
    tasks=${tasks%,}
    echo "Fix the cause, then requeue the failed tasks and submit the merge again:"
    echo "    scontrol requeue $tasks"
    [[ -n $merge ]] && echo "    scancel $merge"
    echo "    sbatch --dependency=afterok:${tasks//,/:} ...the merge job's options... tools/farm/slurm_merge.sh"
    exit 1
fi
((waiting == 0)) || exit 3
