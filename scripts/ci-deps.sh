#!/usr/bin/env bash
# Installs what the firmware simulator (issue 6) needs: the Cortex-M4F
# Rust target and QEMU's Arm system emulator. Idempotent: skips what is
# already there. Called by scripts/test.sh before the tests.
set -euo pipefail

if command -v rustup >/dev/null 2>&1; then
    if ! rustup target list --installed | grep -qx thumbv7em-none-eabihf; then
        rustup target add thumbv7em-none-eabihf
    fi
else
    echo "ci-deps: rustup not found; the thumbv7em-none-eabihf target must already be installed" >&2
fi

if ! command -v qemu-system-arm >/dev/null 2>&1; then
    SUDO=""
    if [ "$(id -u)" != 0 ] && command -v sudo >/dev/null 2>&1; then SUDO="sudo"; fi
    $SUDO apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq qemu-system-arm >/dev/null
fi
qemu-system-arm --version | head -n 1
