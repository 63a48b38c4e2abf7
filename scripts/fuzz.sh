#!/usr/bin/env bash
# Runs every fuzz target (fuzz/fuzz_targets/) for a bounded time each.
# Usage: scripts/fuzz.sh [SECONDS]     (default 60 s per target)
#
# Installs what it needs (a nightly toolchain, cargo-fuzz) itself; CI does
# not run this (it runs the targets' bodies over the seed corpus on stable:
# tests/fuzz_corpus.rs). Each target starts from fuzz/corpus/<target>/ and
# writes new inputs to fuzz/corpus-new/<target>/ (not committed), so the
# repository's seeds stay small. A crash leaves its input under
# fuzz/artifacts/<target>/ and stops the script with a non-zero status.
set -euo pipefail
cd "$(dirname "$0")/.."
SECONDS_EACH="${1:-60}"
case "$SECONDS_EACH" in
    ''|*[!0-9]*) echo "usage: scripts/fuzz.sh [SECONDS]  (a whole number)" >&2; exit 2 ;;
esac

rustup toolchain list | grep -q '^nightly' || rustup toolchain install nightly --profile minimal
command -v cargo-fuzz >/dev/null 2>&1 || cargo install cargo-fuzz --locked

for target in coefficients tracks kite_spec deframer; do
    echo "== fuzz $target for ${SECONDS_EACH} s"
    mkdir -p "fuzz/corpus-new/$target"
    # -max_len keeps inputs near the readers' real sizes (a coefficient
    # file is at most 12 KiB); -rss_limit_mb catches unbounded allocation.
    cargo +nightly fuzz run "$target" "fuzz/corpus-new/$target" "fuzz/corpus/$target" -- \
        -max_total_time="$SECONDS_EACH" -max_len=16384 -rss_limit_mb=2048
done
echo "== every target ran ${SECONDS_EACH} s without a crash"
