#!/usr/bin/env bash
# What writing the outputs costs: for every preset (or those named), the
# CPU of `morphogen verify` (the simulation alone) and of `morphogen run`
# (simulation + stream.bin, records.jsonl, PNG/OBJ/CSV), and their ratio,
# and what the outputs add (run − verify), as a markdown table on standard
# output, then a line with the ratios' least, median and greatest (the
# presets named) and how many meet the goal: outputs written in at most
# 1.3x the simulation or at most 0.3 s more. Non-interactive.
#
#   scripts/bench-outputs.sh [--runs N] [--instructions] [--bin PATH] [PRESET …]
#
# CPU is user + system seconds of the whole process (all threads, to
# 0.1 ms), the median of N runs (default 5), verify and run interleaved
# so that load on a busy machine hits both alike. --instructions counts instructions with
# valgrind (callgrind) instead: one run each, stable, ~50x slower. It
# adds two columns: the instructions `run` spends in the png crate's
# encoder (`write_image_data`: filtering and fdeflate's fastest
# compression of every picture and animation frame), and the ratio run /
# verify would have if that were all the outputs cost: the least any
# `run` that writes these pictures as compressed PNGs could reach.
# The binary is built with `cargo build --release -p morphogen-cli` unless
# --bin is given (CARGO_TARGET_DIR is honoured).
set -euo pipefail

runs=5
mode=cpu
bin=
presets=()
while (($#)); do
    case "$1" in
    --runs) runs="$2"; shift 2 ;;
    --instructions) mode=instructions; shift ;;
    --bin) bin="$2"; shift 2 ;;
    -h | --help) sed -n '2,16p' "$0"; exit 0 ;;
    *) presets+=("$1"); shift ;;
    esac
done

root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root" # verify finds fixtures/ from here
if [[ -z "$bin" ]]; then
    (cd "$root" && cargo build --release -q -p morphogen-cli)
    bin="${CARGO_TARGET_DIR:-$root/target}/release/morphogen"
elif [[ "$bin" != /* ]]; then
    bin="$OLDPWD/$bin"
fi
if ((${#presets[@]} == 0)); then
    mapfile -t presets < <("$bin" list | awk '{print $1}')
fi
scratch="$(mktemp -d)"
trap 'rm -rf "$scratch"' EXIT
: >"$scratch/ratios"
: >"$scratch/floors"

# The cost of one command: CPU seconds or instructions (its profile kept
# in $scratch/profile).
cost() {
    if [[ "$mode" == instructions ]]; then
        valgrind --tool=callgrind --callgrind-out-file="$scratch/profile" "$@" \
            2>&1 >/dev/null | awk '/Collected :/ {print $4}'
    else
        # getrusage of the child: microseconds, where time(1) prints
        # hundredths (a small preset's verify would read 0.00). Less what
        # the interpreter's children had used before (a python3 that is
        # a wrapper script execs with its own children counted).
        python3 -c '
import resource, subprocess, sys
cpu = lambda u: u.ru_utime + u.ru_stime
before = cpu(resource.getrusage(resource.RUSAGE_CHILDREN))
subprocess.run(sys.argv[1:], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
print(f"{cpu(resource.getrusage(resource.RUSAGE_CHILDREN)) - before:.4f}")' "$@"
    fi
}

median() { sort -g | awk '{v[NR] = $1} END {print v[int((NR + 1) / 2)]}'; }

if [[ "$mode" == instructions ]]; then
    unit="instructions"
    n=1
else
    unit="CPU s, median of $runs"
    n="$runs"
fi
# The instructions of the last profile in the PNG encoder (every
# instantiation of png's Writer::write_image_data, inclusive).
png_encoding() {
    callgrind_annotate --inclusive=yes "$scratch/profile" 2>/dev/null |
        awk '/write_image_data \[/ {gsub(",", "", $1); s += $1} END {print s + 0}'
}

if [[ "$mode" == instructions ]]; then
    echo "| preset | verify ($unit) | run ($unit) | run / verify | PNG encoding in run | run / verify, PNG alone |"
    echo "|---|---:|---:|---:|---:|---:|"
else
    echo "| preset | verify ($unit) | run ($unit) | run / verify | outputs (run − verify, s) |"
    echo "|---|---:|---:|---:|---:|"
fi
for p in "${presets[@]}"; do
    : >"$scratch/verify"
    : >"$scratch/run"
    for ((i = 0; i < n; i++)); do
        cost "$bin" verify "$p" >>"$scratch/verify"
        rm -rf "$scratch/out"
        cost "$bin" run "$p" --out "$scratch/out" >>"$scratch/run"
    done
    v="$(median <"$scratch/verify")"
    r="$(median <"$scratch/run")"
    ratio="$(awk -v v="$v" -v r="$r" 'BEGIN {if (v > 0) printf "%.2f", r / v; else print "n/a"}')"
    if [[ "$mode" == instructions ]]; then
        png="$(png_encoding)"
        floor="$(awk -v v="$v" -v p="$png" 'BEGIN {if (v > 0) printf "%.2f", 1 + p / v; else print "n/a"}')"
        echo "| $p | $v | $r | $ratio | $png | $floor |"
        echo "$floor" >>"$scratch/floors"
        echo "$ratio $p" >>"$scratch/ratios"
    else
        extra="$(awk -v v="$v" -v r="$r" 'BEGIN {printf "%.3f", r - v}')"
        echo "| $p | $v | $r | $ratio | $extra |"
        echo "$ratio $p $extra" >>"$scratch/ratios"
    fi
done

# The summary: least, median and greatest ratio, and the presets that
# meet the goal (in CPU mode: at most 1.3x, or at most 0.3 s more).
echo
sort -g "$scratch/ratios" | awk -v unit="$unit" '
    $1 ~ /^[0-9.]+$/ {
        r[++n] = $1; name[n] = $2
        if ($1 <= 1.3) met++
        if ($1 <= 1.3 || ($3 != "" && $3 <= 0.3)) goal++
    }
    END {
        if (n == 0) exit
        printf "run / verify (%s): min %s (%s), median %s, max %s (%s); %d of %d presets <= 1.3\n",
            unit, r[1], name[1], r[int((n + 1) / 2)], r[n], name[n], met, n
        if (unit !~ /^instructions/)
            printf "outputs written in <= 1.3x the simulation or <= 0.3 s more: %d of %d presets\n", goal, n
    }'
if [[ -s "$scratch/floors" ]]; then
    awk '$1 > 1.3 {over++} END {
        printf "%d of %d presets would be over 1.3 with PNG encoding their only output\n", over, NR
    }' "$scratch/floors"
fi
