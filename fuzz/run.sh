#!/usr/bin/env bash
# Runs every fuzz target for RUNS executions (default 100000), each capped at
# FUZZ_MAX_TIME seconds (default 900), and prints the executions per target.
#
#   fuzz/run.sh [RUNS]                 # from the repository root or from fuzz/
#   FUZZ_TARGETS="obj" fuzz/run.sh 1000000
#
# Seeds: the shipped scenes/*.ron, scenes/*.obj and scripts/*.rhai, plus the hand-written
# fuzz/seeds/<target>/ and every input that ever crashed a target (fuzz/regressions/<target>/).
# What the fuzzer learns goes to fuzz/corpus/<target>/ and crashes to fuzz/artifacts/<target>/
# (both git-ignored); a crash is copied into fuzz/regressions/ when fixed (docs/fuzzing.md).
# Needs `cargo install cargo-fuzz`; uses the nightly toolchain when one is installed, else the
# default one (without a sanitizer cargo-fuzz needs no nightly feature). FUZZ_SEED fixes
# libFuzzer's random seed, so a run can be repeated exactly. See docs/fuzzing.md.
set -uo pipefail

runs="${1:-100000}"
max_time="${FUZZ_MAX_TIME:-900}"
targets="${FUZZ_TARGETS:-scene obj script render}"
cd "$(dirname "$0")" || exit 2

declare -A extra=(
    [scene]="-max_len=16384"
    [obj]="-max_len=65536"
    [script]="-max_len=4096"
    [render]="-max_len=16384"
)

toolchain=()
if rustup toolchain list 2>/dev/null | grep -q '^nightly'; then
    toolchain=(+nightly)
fi
seed=()
if [ -n "${FUZZ_SEED:-}" ]; then
    seed=(-seed="$FUZZ_SEED")
fi

# Build once: no sanitizer (penumbra forbids unsafe code, so AddressSanitizer would only
# watch the dependencies, at several times the cost per execution), debug assertions on
# (overflow checks and the code's own debug_asserts, such as the finite-film check).
flags=(--sanitizer none --debug-assertions)
cargo "${toolchain[@]}" fuzz build "${flags[@]}" || exit 2

status=0
summary=""
declare -A shipped=(
    [scene]="../scenes/*.ron"
    [obj]="../scenes/*.obj"
    [script]="../scripts/*.rhai"
    [render]="../scenes/*.ron"
)

for target in $targets; do
    mkdir -p "corpus/$target" "artifacts/$target" "seeds/$target" "regressions/$target"
    # shellcheck disable=SC2086 # the pattern is meant to glob
    cp ${shipped[$target]} "corpus/$target/"
    log="artifacts/$target/last-run.log"
    started=$(date +%s)
    # RAYON_NUM_THREADS=1: one core per fuzzer; grid builds would otherwise spawn a pool.
    RAYON_NUM_THREADS=1 cargo "${toolchain[@]}" fuzz run "${flags[@]}" "$target" "corpus/$target" "seeds/$target" "regressions/$target" -- \
        -runs="$runs" -max_total_time="$max_time" -timeout=10 -rss_limit_mb=4096 \
        -print_final_stats=1 "${seed[@]}" ${extra[$target]} 2>&1 | tee "$log" | grep -E '^(#[0-9]+ +(INITED|DONE|pulse)|Done|==|SUMMARY|thread|panicked)' 
    rc=${PIPESTATUS[0]}
    seconds=$(( $(date +%s) - started ))
    execs=$(grep -oE 'stat::number_of_executed_units: *[0-9]+' "$log" | grep -oE '[0-9]+$' | tail -1)
    if [ "$rc" -ne 0 ]; then
        status=1
        crash=$(grep -oE 'artifacts/[^ ]+' "$log" | tail -1)
        summary+=$(printf '%-7s executions=%-9s seconds=%-5s CRASH rc=%s %s' "$target" "${execs:-?}" "$seconds" "$rc" "$crash")$'\n'
    else
        summary+=$(printf '%-7s executions=%-9s seconds=%-5s ok' "$target" "${execs:-?}" "$seconds")$'\n'
    fi
done
printf '\n== fuzz summary (runs=%s, max %ss per target) ==\n%s' "$runs" "$max_time" "$summary"
exit $status
