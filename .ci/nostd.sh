#!/usr/bin/env bash
# no_std proof for stoss-kernel.
#
# 1. The kernel builds for a bare-metal target without std (thumbv7em-none-eabihf,
#    Cortex-M4F/M7), debug and release.
# 2. tests/no_std_link, a `#![no_std]` static library with its own `#[panic_handler]` that
#    calls the kernel through a C export, builds for the host and for thumbv7em. If anything
#    in the kernel's dependency graph linked `std`, rustc would stop with a duplicate
#    `panic_impl` lang item (E0152).
# 3. The exported symbol is present in both archives (if `nm` is available), and the host
#    archive links into a C program whose result is checked (if a C compiler is available).
#
# Fails on the first error. Usage: bash .ci/nostd.sh (from anywhere).
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"

target=thumbv7em-none-eabihf
link_crate="$root/tests/no_std_link"
link_manifest="$link_crate/Cargo.toml"
# Same directory as tests/no_std_link/.cargo/config.toml, stated explicitly so the result
# does not depend on where cargo looks for configuration.
link_target_dir="$root/target/no_std_link"
symbol=stoss_no_std_link_jc_uniaxial_stress

step() { printf '\n--- nostd: %s\n' "$*"; }

if command -v rustup >/dev/null 2>&1; then
    if ! rustup target list --installed | grep -qx "$target"; then
        step "rustup target add $target"
        rustup target add "$target"
    fi
else
    echo "nostd: rustup not found; assuming the $target standard library is installed" >&2
fi

step "kernel for $target (debug, release)"
cargo build -p stoss-kernel --target "$target"
cargo build -p stoss-kernel --target "$target" --release

step "no_std_link: format and lints"
cargo fmt --manifest-path "$link_manifest" -- --check
cargo clippy --manifest-path "$link_manifest" --target-dir "$link_target_dir" -- -D warnings
cargo clippy --manifest-path "$link_manifest" --target-dir "$link_target_dir" \
    --target "$target" -- -D warnings

step "no_std_link for the host (debug, release)"
cargo build --manifest-path "$link_manifest" --target-dir "$link_target_dir"
cargo build --manifest-path "$link_manifest" --target-dir "$link_target_dir" --release

step "no_std_link for $target (debug, release)"
cargo build --manifest-path "$link_manifest" --target-dir "$link_target_dir" --target "$target"
cargo build --manifest-path "$link_manifest" --target-dir "$link_target_dir" --target "$target" \
    --release

archives=(
    "$link_target_dir/debug/libstoss_no_std_link.a"
    "$link_target_dir/release/libstoss_no_std_link.a"
    "$link_target_dir/$target/debug/libstoss_no_std_link.a"
    "$link_target_dir/$target/release/libstoss_no_std_link.a"
)
for archive in "${archives[@]}"; do
    [[ -s "$archive" ]] || { echo "nostd: missing $archive" >&2; exit 1; }
done

nm_tool=""
for candidate in llvm-nm nm; do
    if command -v "$candidate" >/dev/null 2>&1; then
        nm_tool="$candidate"
        break
    fi
done
if [[ -n "$nm_tool" ]]; then
    step "exported symbol $symbol ($nm_tool)"
    for archive in "${archives[@]}"; do
        # nm may exit non-zero on archive members it cannot parse (e.g. Rust metadata):
        # only its listing matters.
        symbols="$("$nm_tool" -g --defined-only "$archive" 2>/dev/null || true)"
        if ! grep -Eq "[[:space:]]T[[:space:]]+$symbol\$" <<<"$symbols"; then
            echo "nostd: $symbol not defined in $archive" >&2
            exit 1
        fi
        echo "ok: ${archive#"$root/"}"
    done
else
    echo "nostd: no nm found; skipping the symbol check" >&2
fi

cc_tool="${CC:-}"
if [[ -z "$cc_tool" ]]; then
    for candidate in cc gcc clang; do
        if command -v "$candidate" >/dev/null 2>&1; then
            cc_tool="$candidate"
            break
        fi
    done
fi
if [[ -n "$cc_tool" ]]; then
    step "C smoke test: host archives linked into a C program ($cc_tool)"
    scratch="$(mktemp -d)"
    trap 'rm -rf "$scratch"' EXIT
    for profile in debug release; do
        "$cc_tool" -std=c99 -Wall -Wextra -Werror "$link_crate/smoke.c" \
            "$link_target_dir/$profile/libstoss_no_std_link.a" -o "$scratch/smoke-$profile"
        echo "$profile:"
        "$scratch/smoke-$profile"
    done
else
    echo "nostd: no C compiler found; skipping the C smoke test" >&2
fi

printf '\nnostd: OK (kernel and no_std_link build without std for the host and %s)\n' "$target"
