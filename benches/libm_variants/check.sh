#!/usr/bin/env bash
# Does glibc's libm give the same bits with and without FMA on Penumbra's inputs? Builds
# variants.c, runs it with glibc's default (FMA, on a CPU that has it) variants and with its
# pre-FMA ones (GLIBC_TUNABLES), and prints the functions whose results differ. About 4
# minutes on one core. Needs gcc. README ("--simd") gives the result on glibc 2.36.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
gcc -O2 -fno-builtin -o "$work/variants" "$here/variants.c" -lm
"$work/variants" > "$work/default.txt"
GLIBC_TUNABLES=glibc.cpu.hwcaps=-AVX2,-FMA,-AVX512F "$work/variants" > "$work/pre_fma.txt"
ldd --version | head -n 1
if diff "$work/default.txt" "$work/pre_fma.txt" > "$work/diff.txt"; then
    echo "every function agrees:"; cat "$work/default.txt"
else
    echo "differ (< default, > pre-FMA):"; grep '^[<>]' "$work/diff.txt"
fi
