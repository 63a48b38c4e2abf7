#!/usr/bin/env bash
# Installs what the tests need and runs every check and test.
# Usage: scripts/test.sh        (from anywhere; CI runs it through .ci/run)
set -euo pipefail
cd "$(dirname "$0")/.."

# --- what the tests need -----------------------------------------------------
bash scripts/ci-deps.sh            # thumbv7em target, qemu-system-arm
if ! command -v tmux >/dev/null 2>&1; then   # the TUI's end-to-end test drives tmux
    SUDO=""; if [ "$(id -u)" != 0 ] && command -v sudo >/dev/null 2>&1; then SUDO="sudo"; fi
    $SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq tmux >/dev/null
fi
rustup component add rustfmt clippy >/dev/null 2>&1 || true

# --- static checks -----------------------------------------------------------
echo "== cargo fmt --check"
cargo fmt --all -- --check
(cd firmware-sim && cargo fmt --all -- --check)
echo "== clippy (-D warnings; the core also denies unwrap/expect/panic/indexing)"
cargo clippy --workspace --all-targets -- -D warnings
echo "== omniad-core for thumbv7em-none-eabihf (no_std, no alloc)"
cargo build -p omniad-core --target thumbv7em-none-eabihf

# --- tests -------------------------------------------------------------------
echo "== cargo test --workspace (includes the QEMU firmware replay, tests/firmware_replay.rs)"
cargo test --workspace
echo "== firmware per-frame pipeline unit tests (host build; firmware-sim/ is its own workspace)"
cargo test --manifest-path firmware-sim/pipeline/Cargo.toml --target-dir target/fw-pipeline-host
