#!/usr/bin/env bash
# Every check Morphogen has, in the order CI runs them (the README's test
# command; .ci/run calls exactly this). Installs what it needs when missing.
set -euo pipefail
cd "$(dirname "$0")/.."

# Builds for checking, not for a debugger: no incremental cache, and debug
# builds keep line tables only (a backtrace still names file and line). The
# test binaries are a fifth of their size with full debug information, and
# a whole run's build folders fit in a few GB of disk (printed at the end).
export CARGO_INCREMENTAL=0
export CARGO_PROFILE_DEV_DEBUG=line-tables-only

# Each step's time, printed at the end slowest first (the README's "Checks"
# lists them).
timings="$(mktemp)"
shown=""
# Checks that run in the background beside the steps (`beside`), each in
# a process group of its own, its output kept until `joined`.
declare -A beside_pid=() beside_out=()
cleanup() {
    # A check still running in the background: its whole process group
    # (the script, Node.js, Python).
    for pid in "${beside_pid[@]}"; do kill -- -"$pid" 2>/dev/null || true; done
    rm -rf "$timings" "$shown" "${beside_out[@]}"
}
trap cleanup EXIT
step_name=""
step_started=$SECONDS
step_done() {
    [ -z "$step_name" ] || printf '%d\t%s\n' $((SECONDS - step_started)) "$step_name" >>"$timings"
}
step() {
    step_done
    step_name="${*%%:*}"
    step_name="${step_name%% (*}"
    step_started=$SECONDS
    printf '\n==> %s\n' "$*"
}
# beside ID COMMAND...: starts COMMAND in the background, in a process
# group of its own, its output kept for `joined ID`.
beside() {
    local id="$1"
    shift
    beside_out[$id]="$(mktemp)"
    setsid "$@" >"${beside_out[$id]}" 2>&1 &
    beside_pid[$id]=$!
}
# joined ID WHAT: waits for the background check ID, prints its output
# and fails as it failed, naming it WHAT.
joined() {
    local status=0
    wait "${beside_pid[$1]}" || status=$?
    unset "beside_pid[$1]"
    cat "${beside_out[$1]}"
    [ "$status" -eq 0 ] || {
        echo "$2 (run in the background) failed: exit $status" >&2
        exit "$status"
    }
}

step "toolchain: rustfmt, clippy, the Cortex-M targets and RISC-V's riscv32imac"
installed_components=$(rustup component list --installed)
for c in rustfmt clippy; do
    grep -q "^$c" <<<"$installed_components" || rustup component add "$c"
done
installed_targets=$(rustup target list --installed)
for t in thumbv6m-none-eabi thumbv7m-none-eabi thumbv7em-none-eabihf riscv32imac-unknown-none-elf; do
    grep -qx "$t" <<<"$installed_targets" || rustup target add "$t"
done

step "format"
cargo fmt --all --check
(cd firmware-example && cargo fmt --check)
(cd firmware-rp2040 && cargo fmt --check)

step "lint"
# The workspaces of their own repeat the root's lint set word for word.
lints() { awk '/^\[workspace\.lints/ {p = 1} /^\[/ && !/^\[workspace\.lints/ {p = 0} p && NF' "$1"; }
for copy in firmware-example firmware-rp2040 fuzz core/fuzz scripts/peers/lsystem; do
    diff <(lints Cargo.toml) <(lints "$copy/Cargo.toml") >/dev/null || {
        echo "$copy/Cargo.toml: its [workspace.lints] is not the root Cargo.toml's (copy it over)" >&2
        exit 1
    }
done
# One pass over the workspace with the core's optional features on (defmt,
# the rig, the runner on a surface, as the firmware builds it; the
# end-to-end mosaic test's surface runner): the dependencies are checked
# once, with the features every crate sees. The core without features is
# linted as an embedding crate builds it, in the next step but one.
cargo clippy --workspace --all-targets \
    --features morphogen/rig,morphogen/defmt,morphogen/surface-runner,morphogen-scenario/surface-runner -- -D warnings
(cd firmware-example && cargo clippy --release --lib --bins --examples -- -D warnings)
(cd firmware-example && cargo clippy --release --no-default-features --features semihosting,bitwise-crc -- -D warnings)
(cd firmware-example && cargo clippy --release --features surface -- -D warnings)
# The same program on QEMU's RISC-V virt board, as scripts/targets-check.sh builds it.
(cd firmware-example && cargo clippy --release --target riscv32imac-unknown-none-elf \
    --no-default-features --features semihosting,surface -- -D warnings)
# firmware-rp2040 shares firmware-example's target folder: the host-side
# build dependencies (the scenario compiler) are built once.
(cd firmware-rp2040 && CARGO_TARGET_DIR=../firmware-example/target cargo clippy --release -- -D warnings)
# The fuzz targets are linted as the fuzz smoke builds them (below):
# their dependencies are not checked a second time. The L-system
# peer (built where scripts/bench-peers.sh builds it): a few seconds once
# built.
peers_target="$(realpath -m "${CARGO_TARGET_DIR:-target}")/peers"
(cd scripts/peers/lsystem && CARGO_TARGET_DIR="$peers_target" cargo clippy --all-targets -- -D warnings)

step "documentation: cargo doc without a warning (every crate with every feature, the core as docs.rs builds it)"
# Every feature but the core's `bitwise-crc` is the lint pass's set, which
# changes no dependency: the dependencies it checked are reused.
RUSTDOCFLAGS="-D warnings" cargo doc --workspace --no-deps --all-features

step "core check and lint for Cortex-M0+ without features (no_std, no alloc, no atomics: what a crate embedding the core builds; the firmware check builds it with defmt and rig for three Cortex-M targets and runs it)"
cargo clippy -p morphogen --target thumbv6m-none-eabi -- -D warnings

step "core check for RISC-V (riscv32imac: the cores of ESP32-C3, CH32V and GD32V boards; the firmware runs in QEMU's virt machine in scripts/targets-check.sh)"
cargo check -p morphogen --target riscv32imac-unknown-none-elf --features rig

step "the embedding examples build for Cortex-M0+ (firmware-example/examples, profile small), with docs/embedding.md's flash and static RAM, the directly driven horn under 32 KB of flash"
# One build of the four examples, as docs/embedding.md measures them (the
# streams are checked on the host by tests/tests/embedding.rs). `size` is
# binutils', which links every host build.
# The checkout's path mapped to a fixed name, as the firmware check builds
# (scripts/fixed-paths.sh): the same flash on any machine.
(root="$PWD" && . scripts/fixed-paths.sh && cd firmware-example && cargo build --profile small \
    --target thumbv6m-none-eabi --no-default-features --features semihosting,oled --examples)
# Each example's flash and static RAM, summed as the doc's commands sum
# them, against its row of the doc's table. Its peak stack is left out: the
# doc measures it by running the example in QEMU, which CI does not do.
examples="${CARGO_TARGET_DIR:-firmware-example/target}/thumbv6m-none-eabi/small/examples"
grouped() { sed ':a; s/\B[0-9]\{3\}\>/,&/; ta' <<<"$1"; } # 65500 -> 65,500
# table_differs EXAMPLE COLUMN TABLE BUILT: true, and says so, when the
# table's figure is more than 16 B from the built one. Flash moves by a
# few bytes with the checkout's folder, which cargo hashes into the core's
# symbol names, and so into the order of its functions (docs/embedding.md).
table_differs() {
    [ "$3" -gt $(($4 + 16)) ] || [ "$3" -lt $(($4 - 16)) ] || return 1
    echo "docs/embedding.md: $1's $2 is $(grouped "$3") B in the table, $(grouped "$4") B as built (thumbv6m, profile small; more than 16 B apart)" >&2
}
table_wrong=0
for example in horn_direct horn_runner horn_scenario horn_draw; do
    read -r flash ram < <(size -A "$examples/$example" | awk '
        $1 ~ /^\.(vector_table|text|rodata|data)$/ {f += $2}
        $1 ~ /^\.(data|bss|uninit)$/ {r += $2}
        END {print f, r}')
    [ "$example" != horn_direct ] || direct_flash="$flash"
    # The table's row whose example is `NAME.rs`: flash and static RAM are
    # its fourth and fifth columns (awk's fields 5 and 6).
    read -r table_flash table_ram < <(awk -F '|' -v name="\`$example.rs\`" 'index($3, name) {
        gsub(/[^0-9]/, "", $5); gsub(/[^0-9]/, "", $6); print $5, $6; exit }' docs/embedding.md) || {
        echo "docs/embedding.md: no row for $example.rs in the flash and RAM table" >&2
        table_wrong=1
        continue
    }
    if table_differs "$example" flash "$table_flash" "$flash"; then table_wrong=1; fi
    if table_differs "$example" "static RAM" "$table_ram" "$ram"; then table_wrong=1; fi
done
[ "$table_wrong" -eq 0 ] || {
    echo "if the change is meant, write the built figures in docs/embedding.md's table (its commands under \"How the figures are measured\" print them)" >&2
    exit 1
}
[ "$direct_flash" -lt 32768 ] || {
    echo "horn_direct (thumbv6m, profile small): $direct_flash B of flash, not under 32 KB (docs/embedding.md)" >&2
    exit 1
}

step "the Raspberry Pi Pico firmware builds (firmware-rp2040, thumbv6m; no board in CI: it runs in rp2040js in the other-targets step, see its README)"
(cd firmware-rp2040 && CARGO_TARGET_DIR=../firmware-example/target cargo build --release)

step "release build (once: the determinism test, the fixtures, the Python package's wheel and the firmware check reuse it)"
# With the Python package, so that the CLI's dependencies are resolved with
# the features the package adds (pyo3's macros ask more of syn): maturin's
# build then finds them built and compiles the package alone.
cargo build --release -p morphogen-cli -p morphogen-python
morphogen="$(realpath "${CARGO_TARGET_DIR:-target}")/release/morphogen"
export MORPHOGEN_RELEASE_BIN="$morphogen"

step "tests"
cargo test --workspace --no-run
# The Pico's check (scripts/targets-check.sh pico: its firmware built with
# six presets, then some 5 min in rp2040js, a single-threaded emulator)
# starts once the tests are built, in its own process group, and runs
# beside the tests, whose binaries often leave a core idle, and the next
# steps; the other-targets step waits for it. What it installs is
# installed first, in the foreground, so that no two apt-get run at once.
MORPHOGEN_BIN="$morphogen" bash scripts/targets-check.sh --prepare pico
beside pico env MORPHOGEN_BIN="$morphogen" bash scripts/targets-check.sh pico
cargo test --workspace
# The runner with a surface mosaic (the firmware's feature `surface`): the
# scenario crate's test, which builds the core and that crate alone again.
cargo test -p morphogen-scenario --features surface-runner --test runner

step "golden fixtures: every built-in scenario re-run (release build)"
"$morphogen" verify

step "other targets, bit-exact (scripts/targets-check.sh): every preset on s390x (big-endian) under qemu-user, its stream against its fixture; the firmware's MCU presets on riscv32imac in qemu-system-riscv32; the Pico's firmware in rp2040js (started once the tests are built), one preset per model, its UART, OLED and LED matrix"
MORPHOGEN_BIN="$morphogen" bash scripts/targets-check.sh s390x riscv32
joined pico "the Pico's check (scripts/targets-check.sh pico)"

# The Python checks (the reader, the package, vpype, the cluster recipes:
# scripts/python-checks.sh) wait on pip, the disk and one Python thread
# for much of their time: they run beside the next three steps, whose
# cores they share, and are joined before the web page's.
beside python env CHECK_TIMINGS="$timings" MORPHOGEN_BIN="$morphogen" bash scripts/python-checks.sh

step "every preset's scenario file, shown and run from a file, gives its fixture"
shown=$(mktemp -d)
for name in $("$morphogen" list | cut -d' ' -f1); do
    "$morphogen" show "$name" >"$shown/$name.toml"
    "$morphogen" run "$shown/$name.toml" --out "$shown/out-$name" >/dev/null
    cmp "$shown/out-$name/stream.bin" "fixtures/$name/stream.bin"
    rm -rf "$shown/out-$name"
done
echo "all $(ls "$shown" | wc -l) scenario files reproduce their fixtures"

step "boundary probe: every number of one preset per model at both ends of its range, refused or run, never a panic (docs/robustness.md)"
python3 scripts/boundary-probe.py --bin "$morphogen" --timeout 5 \
    growth-curve ram-horn cow-growth long-bone croton-mcu watermelon-mcu

step "fuzz smoke: every reader's libFuzzer target, linted as it builds, for 20 s, as many at a time as there are cores (docs/robustness.md)"
# Built with clippy's driver as the compiler of the fuzz crates' own code,
# as `cargo clippy` runs it, warnings denied: linted and built in one pass
# (clippy's driver leaves MIR unoptimised for its lints; nothing measures
# these builds).
RUSTC_WORKSPACE_WRAPPER="$(dirname "$(rustup which cargo-clippy)")/clippy-driver" CLIPPY_ARGS="-Dwarnings" \
    bash scripts/fuzz.sh 20

step "the Python checks, run beside the last three steps: the stream reader, the package, vpype, the cluster recipes (scripts/python-checks.sh; each part's own time is listed with the steps)"
joined python "the Python checks (scripts/python-checks.sh)"

step "the web page: every preset in Chromium through WebAssembly, bit-exact (Playwright)"
MORPHOGEN_RELEASE_BIN="$morphogen" bash scripts/web-check.sh

step "firmware in QEMU, bit-exact against the fixtures (the boots that do not feed each other run at once)"
MORPHOGEN_BIN="$morphogen" MORPHOGEN_VERIFY="$morphogen verify --stream" MORPHOGEN_BLESS="$morphogen bless" \
  MORPHOGEN_LISTEN="$morphogen listen" MORPHOGEN_SEND="$morphogen send" bash scripts/firmware-check.sh

step_done
printf '\nall checks passed in %d min; the slowest steps:\n' $((SECONDS / 60))
sort -rn "$timings" | head -n 8 | awk -F '\t' '{ printf "  %4d s  %s\n", $1, $2 }'
printf 'build folders on disk:\n'
du -sh "${CARGO_TARGET_DIR:-target}" firmware-example/target fuzz/target web/node_modules 2>/dev/null | sed "s/^/  /" || true
