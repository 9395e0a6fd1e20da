#!/usr/bin/env bash
# Fuzz smoke: builds every cargo-fuzz target of core/fuzz (the core's
# readers) and fuzz/ (the host's readers) and runs each for SECONDS (default
# 20), as many at a time as the machine has cores (FUZZ_JOBS; each libFuzzer
# process is single-threaded). Prints one line per target, in the order
# below, and exits non-zero if any target crashed (its input is in
# <crate>/artifacts/<target>/).
#
#   bash scripts/fuzz.sh [SECONDS]
#   FUZZ_TARGETS="mask scenario" bash scripts/fuzz.sh 600   # some targets
#   FUZZ_JOBS=1 bash scripts/fuzz.sh 600                     # one after the other
#
# Runs on the stable toolchain: RUSTC_BOOTSTRAP=1 lets it take the nightly
# flags cargo-fuzz passes (-Zsanitizer=address). Installs cargo-fuzz if it
# is missing. Seeds are <crate>/seeds/<target>/ (committed); what libFuzzer
# adds goes to <crate>/corpus/<target>/ (ignored). Both crates build into
# fuzz/target/ (shared dependencies build once); logs go to
# fuzz/target/fuzz-logs/. docs/robustness.md, "Fuzzing".
set -euo pipefail

seconds="${1:-20}"
jobs="${FUZZ_JOBS:-$(getconf _NPROCESSORS_ONLN)}"
case "$seconds$jobs" in
'' | *[!0-9]*)
    echo "usage: [FUZZ_JOBS=N] bash scripts/fuzz.sh [SECONDS]" >&2
    exit 2
    ;;
esac
[ "$jobs" -ge 1 ] || jobs=1
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
export RUSTC_BOOTSTRAP=1
target_dir="$root/fuzz/target"
logs="fuzz/target/fuzz-logs"

# crate directory:target
all_targets=(
    core/fuzz:parse
    core/fuzz:derive_buffered
    core/fuzz:decode
    fuzz:scenario
    fuzz:mask
    fuzz:obj_cylinders
    fuzz:capture
)

# libFuzzer options for every target: memory caps (a reader must refuse
# what does not fit, not allocate it), input size, and a per-input time
# limit that tells a hang (an unbounded loop) from a slow input: each
# target's slowest input takes under a second (printed per target), so a
# loaded machine is far from it.
options=(
    -rss_limit_mb=1024
    -malloc_limit_mb=512
    -max_len=65536
    -timeout=20
    -print_final_stats=1
)

if ! cargo fuzz --version >/dev/null 2>&1; then
    echo "fuzz: installing cargo-fuzz"
    # As published: not through a compiler wrapper the build below may be
    # given (scripts/check.sh lints the targets with clippy's driver).
    env -u RUSTC_WORKSPACE_WRAPPER -u CLIPPY_ARGS cargo install cargo-fuzz --locked
fi

selected=()
for entry in "${all_targets[@]}"; do
    if [ -z "${FUZZ_TARGETS:-}" ] || [[ " $FUZZ_TARGETS " == *" ${entry#*:} "* ]]; then
        selected+=("$entry")
    fi
done
if [ "${#selected[@]}" -eq 0 ]; then
    echo "fuzz: no target matches FUZZ_TARGETS='$FUZZ_TARGETS'" >&2
    exit 2
fi

started=$SECONDS
built=""
for entry in "${selected[@]}"; do
    dir="${entry%%:*}"
    case " $built " in *" $dir "*) continue ;; esac
    echo "fuzz: building $dir"
    mkdir -p "$logs"
    build_log="$logs/build-${dir//\//-}.log"
    cargo fuzz build --fuzz-dir "$dir" --target-dir "$target_dir" >"$build_log" 2>&1 || {
        tail -n 30 "$build_log" >&2
        echo "fuzz: build of $dir failed (whole log: $build_log)" >&2
        exit 1
    }
    built="$built $dir"
done
build_time=$((SECONDS - started))

# fuzz_one ENTRY: runs one target for $seconds (the binary cargo-fuzz
# built, with the arguments `cargo fuzz run` gives it), its log in
# $logs/<target>.log and its exit status in $logs/<target>.status.
fuzz_one() {
    local dir="${1%%:*}" target="${1#*:}" status=0
    local corpus="$dir/corpus/$target"
    mkdir -p "$corpus" "$dir/artifacts/$target"
    "$target_dir/$triple/release/$target" -artifact_prefix="$root/$dir/artifacts/$target/" \
        "${options[@]}" -max_total_time="$seconds" \
        "$corpus" "$dir/seeds/$target" >"$logs/$target.log" 2>&1 || status=$?
    echo "$status" >"$logs/$target.status"
}

# report ENTRY: one line for a target that ran; sets `failed` on a crash.
report() {
    local dir="${1%%:*}" target="${1#*:}"
    local log="$logs/$target.log" status runs units slowest artifact
    status="$(cat "$logs/$target.status")"
    runs="$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)"
    if [ -z "$runs" ]; then
        runs="$(grep -o '^#[0-9]*' "$log" | tail -n 1 | tr -d '#' || true)"
    fi
    # libFuzzer's corpus at the end: units/bytes.
    units="$(grep -E '^#[0-9]+' "$log" | tail -n 1 | sed -n 's/.* corp: \([^ ]*\).*/\1/p' || true)"
    slowest="$(sed -n 's/^stat::slowest_unit_time_sec: *//p' "$log" | tail -n 1)"
    [ "$slowest" != 0 ] || slowest="< 1" # whole seconds
    if [ "$status" -eq 0 ]; then
        printf 'fuzz %-16s %10s runs  corpus %-14s 0 crashes  slowest input %s s\n' \
            "$target" "${runs:-?}" "${units:-?}" "${slowest:-?}"
    else
        failed=1
        artifact="$(sed -n 's/.*Test unit written to //p' "$log" | tail -n 1)"
        printf 'fuzz %-16s %10s runs  corpus %-14s CRASH (exit %s): %s\n' \
            "$target" "${runs:-?}" "${units:-?}" "$status" "${artifact:-see $log}"
        grep -m 1 -E 'panicked at|ERROR: (AddressSanitizer|libFuzzer)' "$log" | sed 's/^/    /' >&2 || true
        echo "    reproduce: RUSTC_BOOTSTRAP=1 cargo fuzz run --fuzz-dir $dir --target-dir $target_dir $target ${artifact:-<input>}" >&2
        echo "    log: $log" >&2
    fi
}

# In batches of $jobs, reported in order once a batch is done.
triple="$(rustc -vV | sed -n 's/^host: //p')"
failed=0
for ((i = 0; i < ${#selected[@]}; i += jobs)); do
    batch=("${selected[@]:i:jobs}")
    for entry in "${batch[@]}"; do fuzz_one "$entry" & done
    wait
    for entry in "${batch[@]}"; do report "$entry"; done
done
echo "fuzz: ${#selected[@]} targets, ${seconds} s each, $jobs at a time; build ${build_time} s, total $((SECONDS - started)) s"
exit "$failed"
