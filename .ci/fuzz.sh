#!/usr/bin/env bash
# Bounded fuzzing of stoss-kernel and its C ABI with cargo-fuzz (libFuzzer), see fuzz/README.md.
#
# 1. Installs cargo-fuzz if missing (`cargo install cargo-fuzz --locked`).
# 2. Builds every target, i.e. every [[bin]] of fuzz/Cargo.toml (`cargo fuzz list`), abi_batch
#    included (no sanitizer: the kernel has no unsafe code; the harness checks properties).
#    Stable Rust first; if stable refuses, RUSTC_BOOTSTRAP=1.
# 3. Replays the committed reproducers of kernel defects the fuzzers found
#    (fuzz/regressions/<target>/), which also live as tests in kernel/tests/fuzz_regressions.rs.
# 4. Fuzzes every target for FUZZ_SECONDS (default 60), FUZZ_JOBS (default: the cores, at most
#    4) at once, from its committed seed corpus
#    (fuzz/corpus/<target>/), writing new inputs to a scratch directory so the committed
#    corpus stays small. Prints executions per second and total executions per target.
#
# Fails if any target crashes (artifacts in fuzz/artifacts/<target>/, reproduce with
# `cargo fuzz run -s none <target> <artifact>` from fuzz/). All targets run before it fails.
# Usage: FUZZ_SECONDS=60 bash .ci/fuzz.sh [target...]
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root/fuzz"

seconds="${FUZZ_SECONDS:-60}"
started=$SECONDS
step() { printf '\n--- fuzz: %s (%ds)\n' "$*" "$((SECONDS - started))"; }

if ! command -v cargo >/dev/null 2>&1 && [[ -f "$HOME/.cargo/env" ]]; then
    # shellcheck source=/dev/null
    . "$HOME/.cargo/env"
fi
if ! cargo fuzz --version >/dev/null 2>&1; then
    step "cargo install cargo-fuzz --locked"
    cargo install cargo-fuzz --locked
fi
cargo fuzz --version

# libFuzzer is C++ and is compiled by the libfuzzer-sys build script.
if ! command -v c++ >/dev/null 2>&1 && ! command -v g++ >/dev/null 2>&1 \
    && ! command -v clang++ >/dev/null 2>&1; then
    echo "fuzz: a C++ compiler is needed to build libFuzzer (apt-get install g++)" >&2
    exit 1
fi

step "build (sanitizer none)"
if ! cargo fuzz build -s none; then
    echo "fuzz: stable refused the build; retrying with RUSTC_BOOTSTRAP=1" >&2
    export RUSTC_BOOTSTRAP=1
    cargo fuzz build -s none
fi

if [[ $# -gt 0 ]]; then
    targets=("$@")
else
    mapfile -t targets < <(cargo fuzz list)
fi

scratch="$(mktemp -d)"
trap 'rm -rf "$scratch"' EXIT
# libFuzzer options: a hang is a failure (10 s for an input that takes microseconds), no
# leak detection (no sanitizer), final statistics for the exec/s line.
options=(-timeout=10 -print_final_stats=1)

# Each libFuzzer process is single-threaded, so FUZZ_JOBS targets (default: the number of
# cores, at most 4) fuzz at once; every target still gets its full FUZZ_SECONDS. Each
# target's outcome goes to $scratch/<target>.line (and .failed), read back in target order.
jobs="${FUZZ_JOBS:-$(nproc 2>/dev/null || echo 1)}"
if ! [[ "$jobs" =~ ^[1-9][0-9]*$ ]]; then
    echo "fuzz: FUZZ_JOBS must be a positive integer, got '$jobs'" >&2
    exit 2
fi
if ((jobs > 4)); then
    jobs=4
fi

fuzz_target() {
    local target="$1" log status=0 runs rate line artifact
    mkdir -p "$scratch/$target" "corpus/$target"
    log="$scratch/$target.log"
    cargo fuzz run -s none "$target" "$scratch/$target" "corpus/$target" -- \
        -max_total_time="$seconds" "${options[@]}" >"$log" 2>&1 || status=$?
    runs="$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)"
    rate="$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -n 1)"
    line="$target: ${runs:-?} executions, ${rate:-?} exec/s, $(find "$scratch/$target" -type f | wc -l) new corpus entries"
    if [[ $status -ne 0 ]]; then
        grep -E -A3 "panicked at|ERROR: libFuzzer|SUMMARY" "$log" | head -n 12 >&2 || true
        artifact="$(sed -n 's/.*Test unit written to \(.*\)$/\1/p' "$log" | tail -n 1)"
        echo "fuzz: $target crashed (exit $status); artifact: ${artifact:-see log}" >&2
        line="$line, CRASH ${artifact:-}"
        touch "$scratch/$target.failed"
    fi
    echo "$line" >"$scratch/$target.line"
}

failed=()
summary=()

for target in "${targets[@]}"; do
    if [[ -d "regressions/$target" ]] && compgen -G "regressions/$target/*" >/dev/null; then
        step "$target: reproducers of fixed defects (fuzz/regressions/$target)"
        # Given files (not directories), libFuzzer runs each once and stops.
        if ! cargo fuzz run -s none "$target" regressions/"$target"/* -- "${options[@]}" \
            >"$scratch/$target.regressions.log" 2>&1; then
            grep -E -A3 "panicked at" "$scratch/$target.regressions.log" | head -n 8 >&2 || true
            echo "fuzz: $target: a defect in fuzz/regressions/$target reproduces" \
                "(see kernel/tests/fuzz_regressions.rs)" >&2
            failed+=("$target (regression)")
        else
            echo "ok: every reproducer passes"
        fi
    fi
done

step "fuzzing ${#targets[@]} targets, ${seconds}s each, $jobs at a time"
running=0
for target in "${targets[@]}"; do
    fuzz_target "$target" &
    running=$((running + 1))
    if ((running >= jobs)); then
        wait -n || true
        running=$((running - 1))
    fi
done
wait || true

for target in "${targets[@]}"; do
    if [[ -f "$scratch/$target.line" ]]; then
        line="$(cat "$scratch/$target.line")"
    else
        line="$target: no result (the fuzzing job died)"
    fi
    if [[ -f "$scratch/$target.failed" || ! -f "$scratch/$target.line" ]]; then
        failed+=("$target")
    fi
    echo "$line"
    summary+=("$line")
done

printf '\n--- fuzz: summary (%ds)\n' "$((SECONDS - started))"
printf '%s\n' "${summary[@]}"
if [[ ${#failed[@]} -gt 0 ]]; then
    printf 'fuzz: FAILED: %s\n' "${failed[*]}" >&2
    exit 1
fi
echo "fuzz: OK (${#targets[@]} targets, ${seconds}s each)"
