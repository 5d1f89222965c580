#!/usr/bin/env bash
# Side-by-side timing of stoss's kernel (through the Abaqus VUMAT adapter of its C ABI) and a
# plain hand-written Johnson-Cook VUMAT in Fortran, on the same problem in one process
# (issue 14). Builds the release static library, compiles both with gfortran -O2 (no -march,
# as the Rust side has no target-cpu), and prints ns per plastic point-update.
#
# Usage: kernel/ffi/benches/fortran_peer/run.sh [rounds]        (about 10 s for 9 rounds)
#        kernel/ffi/benches/fortran_peer/run.sh --compile-only   (CI: build, do not time)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../../../.." && pwd)"
here="$root/kernel/ffi/benches/fortran_peer"
cd "$root"
cargo build --quiet --release -p stoss-kernel-ffi
target_dir="$(cargo metadata --format-version 1 --no-deps \
    | grep -o '"target_directory":"[^"]*"' | head -1 | sed 's/.*:"\(.*\)"/\1/')"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
gfortran -std=f2018 -O2 -Wall -Wextra -Wno-compare-reals -Werror -fimplicit-none \
    -J "$work" "$here/jc_vumat_peer.f90" "$here/peer_bench.f90" \
    "$target_dir/release/libstoss_kernel_ffi.a" -lgcc_s -lutil -lrt -lpthread -lm -ldl -lc \
    -o "$work/peer_bench"
if [[ "${1:-}" == "--compile-only" ]]; then
    echo "fortran peer bench compiles"
    exit 0
fi
"$work/peer_bench" "${1:-9}"
