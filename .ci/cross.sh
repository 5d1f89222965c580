#!/usr/bin/env bash
# Cross-target bit-exactness for stoss-kernel.
#
# 1. The golden histories (tests/golden.rs, fixtures/golden/*.golden, stored as exact f64 bit
#    patterns written on x86_64) are recomputed on aarch64-unknown-linux-gnu in release and
#    compared bit for bit (debug against release is compared on x86_64 in .ci/run).
#    The test binaries run under qemu user-mode emulation
#    (qemu-aarch64-static or qemu-aarch64, with the Debian arm64 cross libc as sysroot).
# 2. aarch64 has fused multiply-add instructions; rustc never contracts a*b+c into them unless
#    the source asks (f64::mul_add), and neither crate does. As evidence beside the passing
#    goldens, the release test binary's stoss code is disassembled and must hold no
#    fmadd/fmsub/fnmadd/fnmsub (skipped if the cross objdump is missing).
# 3. The kernel builds for thumbv7em-none-eabihf (Cortex-M4F/M7, no std), debug and release.
# 4. Host determinism: tests/determinism.rs (hashes of `stoss synthesize` outputs pinned on
#    x86_64) passes on aarch64 under qemu.
#
# Installs what is missing: qemu-user-static (or qemu-user), gcc-aarch64-linux-gnu and
# libc6-dev-arm64-cross through apt-get (sudo if not root), and the two rustup targets.
# Respects CARGO_TARGET_DIR. Fails on the first error. Usage: bash .ci/cross.sh
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"

export DEBIAN_FRONTEND=noninteractive
aarch64=aarch64-unknown-linux-gnu
embedded=thumbv7em-none-eabihf
sysroot=/usr/aarch64-linux-gnu
started=$SECONDS

step() { printf '\n--- cross: %s (%ds)\n' "$*" "$((SECONDS - started))"; }

sudo_cmd=()
if [[ "$(id -u)" -ne 0 ]] && command -v sudo >/dev/null 2>&1; then
    sudo_cmd=(sudo)
fi

apt_updated=0
apt_install() {
    if ! command -v apt-get >/dev/null 2>&1; then
        echo "cross: apt-get not available; please install: $*" >&2
        return 1
    fi
    if [[ $apt_updated -eq 0 ]]; then
        "${sudo_cmd[@]}" apt-get update -qq
        apt_updated=1
    fi
    "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "$@"
}

find_qemu() {
    for candidate in qemu-aarch64-static qemu-aarch64; do
        if command -v "$candidate" >/dev/null 2>&1; then
            echo "$candidate"
            return 0
        fi
    done
    return 1
}

# --- Prerequisites -----------------------------------------------------------------------
step "prerequisites"
missing=()
if ! find_qemu >/dev/null; then
    missing+=(qemu-user-static)
fi
if ! command -v aarch64-linux-gnu-gcc >/dev/null 2>&1; then
    missing+=(gcc-aarch64-linux-gnu)
fi
if [[ ! -e "$sysroot/lib/libc.so" && ! -e "$sysroot/lib/libc.so.6" ]] \
    || [[ ! -e "$sysroot/include/stdio.h" ]]; then
    missing+=(libc6-dev-arm64-cross)
fi
if [[ ${#missing[@]} -gt 0 ]]; then
    echo "cross: installing ${missing[*]}"
    if ! apt_install "${missing[@]}"; then
        # Some distributions ship only the dynamically linked emulator.
        if [[ " ${missing[*]} " == *" qemu-user-static "* ]]; then
            echo "cross: qemu-user-static failed, trying qemu-user" >&2
            apt_install "${missing[@]/qemu-user-static/qemu-user}"
        else
            exit 1
        fi
    fi
fi
qemu="$(find_qemu)" || { echo "cross: no qemu-aarch64 found" >&2; exit 1; }

if command -v rustup >/dev/null 2>&1; then
    installed="$(rustup target list --installed)"
    for target in "$aarch64" "$embedded"; do
        if ! grep -qx "$target" <<<"$installed"; then
            rustup target add "$target"
        fi
    done
else
    echo "cross: rustup not found; assuming the $aarch64 and $embedded std are installed" >&2
fi

export CARGO_TARGET_AARCH64_UNKNOWN_LINUX_GNU_LINKER=aarch64-linux-gnu-gcc
export CARGO_TARGET_AARCH64_UNKNOWN_LINUX_GNU_RUNNER="$qemu -L $sysroot"
# Build scripts and proc macros still build for the host; only the target C compiler changes.
export CC_aarch64_unknown_linux_gnu=aarch64-linux-gnu-gcc
"$qemu" --version | head -n 1
aarch64-linux-gnu-gcc --version | head -n 1

# --- Golden histories on aarch64 ---------------------------------------------------------
# Release only: the debug profile (opt-level 1) is compared with release (opt-level 3) on
# x86_64 in .ci/run, and rustc's float semantics do not depend on the optimisation level; the
# aarch64 debug build of the whole host cost about four minutes of CI for no further evidence.
step "golden histories on $aarch64 under qemu (release)"
cargo test -p stoss --test golden --target "$aarch64" --release

step "host determinism on $aarch64 under qemu: synthetic recordings hash as on x86_64"
cargo test -p stoss --test determinism --target "$aarch64" --release

step "the kernel's exp, ln and pow on $aarch64 under qemu (oracle bound, result hash)"
cargo test -p stoss-kernel --test math --target "$aarch64" --release

# --- No fused multiply-add in the stoss code of the aarch64 binary ------------------------
objdump_tool=""
for candidate in aarch64-linux-gnu-objdump llvm-objdump; do
    if command -v "$candidate" >/dev/null 2>&1; then
        objdump_tool="$candidate"
        break
    fi
done
if [[ -n "$objdump_tool" ]]; then
    step "no FMA contraction in the stoss code of the release golden binary ($objdump_tool)"
    target_dir="$(cargo metadata --format-version 1 --no-deps \
        | sed -n 's/.*"target_directory":"\([^"]*\)".*/\1/p')"
    binary="$(cargo test -p stoss --test golden --target "$aarch64" --release --no-run \
        --message-format=json 2>/dev/null \
        | sed -n 's/.*"executable":"\([^"]*\)".*/\1/p' | tail -n 1)"
    if [[ -z "$binary" || ! -f "$binary" ]]; then
        echo "cross: golden test binary not found under $target_dir" >&2
        exit 1
    fi
    # Count fused multiply-adds per function; only functions whose demangled name mentions
    # stoss (the kernel, the host library, the test) are held to zero. libm's own routines
    # may use an explicit, correctly rounded fma, which is deterministic.
    report="$("$objdump_tool" -d -C --no-show-raw-insn "$binary" | awk '
        /^[0-9a-f]+ <.*>:$/ { name = $0; next }
        /\t(fmadd|fmsub|fnmadd|fnmsub|fmla|fmls)[ \t]/ {
            total++
            if (name ~ /stoss|golden/) { ours++; print "  " name }
        }
        END { printf "fused multiply-adds: %d in the binary, %d in stoss code\n", total, ours }
    ')"
    tail -n 1 <<<"$report"
    if [[ "$(wc -l <<<"$report")" -gt 1 ]]; then
        echo "cross: fused multiply-add in stoss code:" >&2
        head -n -1 <<<"$report" | sort | uniq -c >&2
        exit 1
    fi
else
    echo "cross: no aarch64 objdump; skipping the FMA disassembly check" >&2
fi

# --- Bare-metal build ----------------------------------------------------------------------
step "stoss-kernel for $embedded (debug, release)"
cargo build -p stoss-kernel --target "$embedded"
cargo build -p stoss-kernel --target "$embedded" --release

printf '\ncross: OK (golden histories bit-identical on %s in release; kernel builds for %s) in %ds\n' \
    "$aarch64" "$embedded" "$((SECONDS - started))"
