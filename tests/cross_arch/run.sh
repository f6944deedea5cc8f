#!/usr/bin/env bash
# The same results on aarch64 (ARM servers, Apple silicon under Linux): builds `vifo` for
# aarch64-unknown-linux-gnu, runs it under qemu-user beside the native build and compares their
# outputs byte for byte (compare.py says what). Installs what it needs where it can: Debian's
# qemu-user and aarch64 cross linker, rustup's aarch64 standard library; where it cannot, it
# prints SKIPPED with the reason and exits 0.
#
# usage: tests/cross_arch/run.sh   (from anywhere; about 6 min to build and 5 to compare on 2 cores)
set -euo pipefail
cd "$(dirname "$0")/../.."

target=aarch64-unknown-linux-gnu
skip() { echo "SKIPPED cross-architecture check: $1"; exit 0; }

if ! command -v qemu-aarch64 >/dev/null || ! command -v aarch64-linux-gnu-gcc >/dev/null \
   || [ ! -e /usr/aarch64-linux-gnu/lib/libc.so ]; then
  sudo=""; [ "$(id -u)" = 0 ] || sudo="sudo -n"
  packages="qemu-user gcc-aarch64-linux-gnu libc6-dev-arm64-cross"
  $sudo apt-get install -y -q $packages >/dev/null 2>&1 \
    || { $sudo apt-get update -q >/dev/null 2>&1 && $sudo apt-get install -y -q $packages >/dev/null 2>&1; } \
    || skip "could not install $packages"
fi
rustup target list --installed 2>/dev/null | grep -q "^$target\$" || rustup target add "$target" >/dev/null 2>&1 \
  || skip "could not add the rustup target $target"

cargo build -q --profile fast -p vifo
# The cross linker is named here, not in .cargo/config.toml, where it would also apply to
# native builds on aarch64 machines that have no such program.
CARGO_TARGET_AARCH64_UNKNOWN_LINUX_GNU_LINKER=aarch64-linux-gnu-gcc \
  cargo build -q --profile fast -p vifo --target "$target"
python3 tests/cross_arch/compare.py --vifo target/fast/vifo \
  --other "qemu-aarch64 -L /usr/aarch64-linux-gnu target/$target/fast/vifo" --work target/cross-arch
