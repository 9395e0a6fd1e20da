# Sourced by the scripts that build for Cortex-M (firmware-check.sh,
# bench.sh), with `root` set to the checkout.
#
# Panic locations name their source files by absolute path, so the flash
# figures would move with the folders the sources sit in (in the
# stream-only build, 14 files of the core and 11 of the registry: 14 B
# of flash per character of the checkout's path). Every Cortex-M build
# maps the checkout and the registry to fixed names (a path with spaces is
# left as it is). A figure still moves by a few bytes with the checkout's
# folder, which cargo hashes into the core's symbol names and so into the
# order of its functions (docs/embedding.md).
registry="${CARGO_HOME:-$HOME/.cargo}/registry/src"
case "$root$registry" in
  *[[:space:]]*) ;;
  *)
    for t in THUMBV6M_NONE_EABI THUMBV7M_NONE_EABI THUMBV7EM_NONE_EABIHF; do
      export "CARGO_TARGET_${t}_RUSTFLAGS=--remap-path-prefix=$root=/morphogen --remap-path-prefix=$registry=/crates"
    done
    ;;
esac
