#!/usr/bin/env bash
# The Slurm executor against a real Slurm: a single-node cluster on this machine
# (.ci/slurm-cluster.sh), then
#   1. a small calibration with --executor slurm (job arrays) and with --slurm-mode allocation,
#      each compared bit for bit with the local run of the same campaign; a diagnosis whose
#      least-squares refits run as Slurm tasks (prediction tasks), compared with the local
#      diagnosis;
#   2. a task cancelled in the queue (scancel of one array element): it is rerun, and the
#      calibration is still the local one;
#   3. the coordinator killed (SIGKILL) mid-run: --resume adopts the results its tasks wrote
#      meanwhile without running them again, and ends on the local result;
#   4. bad set-ups end with a clear error, not a hang: no sbatch on PATH, a partition that does
#      not exist, a run folder the workers cannot see, a time limit shorter than a candidate.
# Needs root. Every wait is bounded; the cluster is stopped and its files removed on exit.
#
# `bash .ci/slurm.sh --measure` instead measures the executor's overhead per candidate: the
# synthetic flow-curve campaign (candidates of milliseconds) with 40 candidates per batch,
# locally and through both Slurm modes, with the same result.
set -euo pipefail
measure=0
[[ "${1:-}" == "--measure" ]] && measure=1

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
# shellcheck source=.ci/slurm-cluster.sh
. "$root/.ci/slurm-cluster.sh"

if [[ "$(id -u)" -ne 0 ]]; then
    echo "slurm: skipped: the single-node cluster needs root" >&2
    exit 0
fi
command -v python3 >/dev/null 2>&1 || {
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends python3-minimal >/dev/null
}

work="$(mktemp -d /tmp/stoss-slurm.XXXXXX)"
cleanup() {
    local status=$?
    slurm_cluster_stop
    rm -rf "$work"
    exit "$status"
}
trap cleanup EXIT

fail() {
    echo "slurm test FAILED: $*" >&2
    exit 1
}

# .ci/run passes the release binary its test step built (STOSS_BIN); alone, build it.
if [[ -n "${STOSS_BIN:-}" && -x "${STOSS_BIN}" ]]; then
    stoss="$STOSS_BIN"
else
    cargo build --release -p stoss
    stoss="$root/target/release/stoss"
fi
slurm_cluster_start "$work/cluster"

# A small campaign whose candidates take about a second each (two Taylor tests and two flow
# curves of the synthetic HHA set): 2 batches of 3, then the finalist.
campaign="$work/campaign.toml"
experiments="$root/fixtures/experiments"
write_campaign() { # write_campaign FILE [extra executor lines...]
    local file="$1"
    shift
    cat >"$file" <<EOF
name = "Slurm executor test (synthetic HHA)"
material = "$root/fixtures/materials/4340-jc.toml"
[[models]]
name = "jc"
[models.parameters]
yield_stress = [0.5e9, 2.0e9]
hardening_modulus = [0.0, 1.5e9]
hardening_exponent = [0.05, 1.0]
rate_sensitivity = [0.0, 0.05]
[[experiments]]
file = "$experiments/synthetic-taylor-hha-184.toml"
[[experiments]]
file = "$experiments/synthetic-taylor-hha-208.toml"
[[experiments]]
file = "$experiments/synthetic-flow-hha-1s.toml"
[[experiments]]
file = "$experiments/synthetic-flow-hha-3000s.toml"
holdout = true
[optimiser]
budget = 6
instances = 1
seed = 7
parallel = 3
polish = 0
[executor]
poll_interval = 0.2
result_wait = 3
probe_timeout = 120
EOF
    local line
    for line in "$@"; do
        echo "$line" >>"$file"
    done
}
write_campaign "$campaign"

if [[ $measure -eq 1 ]]; then
    flow="$work/flow.toml"
    sed -e "s|\"\.\./|\"$root/fixtures/|" -e 's/^parallel = 2/parallel = 40/' \
        "$root/fixtures/campaigns/synthetic-flow.toml" >"$flow"
    printf '[executor]\npoll_interval = 0.2\nresult_wait = 3\n' >>"$flow"
    flags=(--budget 80 --polish 0 --instances 1 --quiet)
    for run in local array allocation; do
        extra=()
        [[ $run != local ]] && extra=(--executor slurm --slurm-mode "$run" --max-concurrent 2)
        started=$(date +%s.%N)
        timeout 1200 "$stoss" calibrate "$flow" --output "$work/m-$run" "${flags[@]}" "${extra[@]}" >/dev/null
        ended=$(date +%s.%N)
        candidates=$(wc -l <"$work/m-$run/simulations.jsonl")
        awk -v r="$run" -v a="$started" -v b="$ended" -v n="$candidates" \
            'BEGIN { printf "%-10s %3d candidates  %7.2f s  %6.3f s per candidate\n", r, n, b - a, (b - a) / n }'
    done
    python3 .ci/compare-calibrations.py "$work/m-local" "$work/m-array"
    python3 .ci/compare-calibrations.py "$work/m-local" "$work/m-allocation"
    exit 0
fi

run_calibration() { # run_calibration OUTPUT [flags...]: a bounded calibration
    local output="$1"
    shift
    timeout 600 "$stoss" calibrate "$campaign" --output "$output" --quiet "$@"
}

echo "=== local reference"
started=$SECONDS
run_calibration "$work/local" >/dev/null
local_seconds=$((SECONDS - started))

echo "=== job arrays: identical to local"
started=$SECONDS
run_calibration "$work/array" --executor slurm >/dev/null
array_seconds=$((SECONDS - started))
python3 .ci/compare-calibrations.py "$work/local" "$work/array" || fail "array run differs from local"
grep -q '"executor":"slurm-array"' "$work/array/simulations.jsonl" || fail "no slurm-array origin logged"

echo "=== one allocation with srun steps: identical to local"
started=$SECONDS
run_calibration "$work/allocation" --executor slurm --slurm-mode allocation --max-concurrent 2 >/dev/null
allocation_seconds=$((SECONDS - started))
python3 .ci/compare-calibrations.py "$work/local" "$work/allocation" || fail "allocation run differs from local"
echo "wall time: local ${local_seconds} s, job arrays ${array_seconds} s, allocation ${allocation_seconds} s"

echo "=== diagnosis refits as Slurm tasks: identical to local"
# The synthetic flow curves (simulations of milliseconds): the refits' many small batches
# cost the executor's overhead only. One allocation, as a diagnosis of long simulations would
# also use it.
flow="$work/flow-diagnosis.toml"
sed -e "s|\"\.\./|\"$root/fixtures/|" "$root/fixtures/campaigns/synthetic-flow.toml" >"$flow"
printf '[executor]\npoll_interval = 0.1\nresult_wait = 3\nprobe_timeout = 120\n' >>"$flow"
timeout 600 "$stoss" calibrate "$flow" --output "$work/diagnosis-local" --budget 12 --polish 0 \
    --instances 1 --quiet >/dev/null
cp -r "$work/diagnosis-local" "$work/diagnosis-slurm"
started=$SECONDS
timeout 600 "$stoss" diagnose "$work/diagnosis-local" --max-refits 1 --iterations 3 --quiet >/dev/null
diagnosis_local_seconds=$((SECONDS - started))
started=$SECONDS
timeout 900 "$stoss" diagnose "$work/diagnosis-slurm" --max-refits 1 --iterations 3 --quiet \
    --executor slurm --slurm-mode allocation --max-concurrent 2 >/dev/null
diagnosis_slurm_seconds=$((SECONDS - started))
grep -q '"executor":"slurm-allocation"' "$work/diagnosis-slurm/diagnosis.jsonl" \
    || fail "no slurm-allocation origin in the diagnosis journal"
compgen -G "$work/diagnosis-slurm/slurm/tasks/predict-*.result.json" >/dev/null \
    || fail "no prediction task ran on the cluster"
python3 - "$work/diagnosis-local/diagnosis/diagnosis.json" "$work/diagnosis-slurm/diagnosis/diagnosis.json" <<'PY' \
    || fail "the diagnosis on Slurm differs from the local one"
import json, sys
local, slurm = (json.load(open(p)) for p in sys.argv[1:3])
for d in (local, slurm):
    d.pop("cost", None)
sys.exit(0 if local == slurm else 1)
PY
echo "diagnosis: local ${diagnosis_local_seconds} s, slurm allocation ${diagnosis_slurm_seconds} s, identical"

# Job names are stoss-<hash of the run folder>; wait for no job of that name to be queued or running.
wait_for_jobs_to_end() { # wait_for_jobs_to_end SECONDS
    local waited=0
    while [[ -n "$(squeue -h -t PENDING,RUNNING,COMPLETING -o %i)" ]]; do
        [[ $waited -lt $1 ]] || fail "jobs still queued after $1 s: $(squeue)"
        sleep 1
        waited=$((waited + 1))
    done
}

echo "=== a task cancelled in the queue is rerun"
# One task at a time, so the later tasks of the first array wait PENDING; cancel one of them.
run_calibration "$work/cancel" --executor slurm --max-concurrent 1 >"$work/cancel.out" 2>&1 &
coordinator=$!
cancelled=""
for _ in $(seq 1 600); do
    pending="$(squeue -h -r -t PENDING -o %i | head -n 1)"
    if [[ -n "$pending" && "$pending" == *_* ]]; then
        scancel "$pending"
        cancelled="$pending"
        break
    fi
    sleep 0.1
done
[[ -n "$cancelled" ]] || fail "no pending array task to cancel within 60 s"
wait "$coordinator" || { cat "$work/cancel.out" >&2; fail "calibration with a cancelled task failed"; }
grep -q '"attempts":2' "$work/cancel/simulations.jsonl" || fail "the cancelled task ($cancelled) was not rerun"
python3 .ci/compare-calibrations.py "$work/local" "$work/cancel" || fail "run with a rerun task differs from local"
echo "cancelled $cancelled; rerun, result identical"

echo "=== the coordinator killed mid-run; --resume adopts finished tasks"
run_calibration "$work/killed" --executor slurm --max-concurrent 1 >/dev/null 2>&1 &
coordinator=$!
for _ in $(seq 1 600); do
    compgen -G "$work/killed/slurm/tasks/*.result.json" >/dev/null && break
    sleep 0.1
done
compgen -G "$work/killed/slurm/tasks/*.result.json" >/dev/null || fail "no task result within 60 s"
# $coordinator is the subshell around `timeout` around stoss: kill stoss itself.
pkill -KILL -f "calibrate $campaign --output $work/killed " || fail "no coordinator process to kill"
wait "$coordinator" 2>/dev/null || true
wait_for_jobs_to_end 120
logged_before="$(wc -l <"$work/killed/simulations.jsonl")"
ls --full-time "$work"/killed/slurm/tasks/*.result.json | awk '{print $6, $7, $9}' >"$work/results-before"
results_before="$(wc -l <"$work/results-before")"
[[ "$results_before" -gt "$logged_before" ]] || fail "no task finished after the kill (logged $logged_before, results $results_before)"
run_calibration "$work/killed" --executor slurm --resume >"$work/resume.out" 2>&1 \
    || { cat "$work/resume.out" >&2; fail "--resume failed"; }
ls --full-time "$work"/killed/slurm/tasks/*.result.json | awk '{print $6, $7, $9}' >"$work/results-after"
while read -r line; do
    grep -qxF "$line" "$work/results-after" || fail "a finished task was run again: $line"
done <"$work/results-before"
python3 .ci/compare-calibrations.py "$work/local" "$work/killed" || fail "resumed run differs from local"
echo "killed with $logged_before logged and $results_before finished; resumed without rerunning them; identical"

expect_error() { # expect_error NAME PATTERN COMMAND...: non-zero exit within 300 s, message matching PATTERN
    local name="$1" pattern="$2"
    shift 2
    local status=0
    timeout 300 "$@" >"$work/$name.out" 2>&1 || status=$?
    [[ $status -ne 0 && $status -ne 124 ]] || { cat "$work/$name.out" >&2; fail "$name: exit $status"; }
    grep -qiE "$pattern" "$work/$name.out" || { cat "$work/$name.out" >&2; fail "$name: message does not match /$pattern/"; }
    echo "$name: $(grep -iE "$pattern" "$work/$name.out" | head -n 1)"
}

echo "=== bad set-ups: clear errors, no hang"
expect_error no-sbatch "sbatch is not on PATH" \
    env PATH=/nonexistent "$stoss" calibrate "$campaign" --output "$work/no-sbatch" --executor slurm --quiet
expect_error bad-partition "error: .*invalid partition" \
    "$stoss" calibrate "$campaign" --output "$work/bad-partition" --executor slurm --partition nosuchpartition --quiet
# A run folder the workers cannot see: the coordinator in a mount namespace of its own, with a
# private filesystem over its output folder.
mkdir -p "$work/unshared"
expect_error unshared-folder "error: .*(share|visible)" \
    unshare --mount --propagation private sh -c \
    "mount -t tmpfs tmpfs '$work/unshared' && exec '$stoss' calibrate '$campaign' --output '$work/unshared/run' --executor slurm --quiet"
# A candidate longer than the time limit (Slurm's smallest limit is a minute: the tasks of
# arrays are slowed past it by a prologue; the probe is not an array task).
write_campaign "$work/slow.toml" 'retries = 0' 'time_limit = "1"' \
    'prologue = ["[ -z \"$SLURM_ARRAY_TASK_ID\" ] || sleep 150"]'
expect_error time-limit "time limit" \
    "$stoss" calibrate "$work/slow.toml" --output "$work/slow" --executor slurm --quiet
wait_for_jobs_to_end 60
echo "=== slurm: all checks passed"
