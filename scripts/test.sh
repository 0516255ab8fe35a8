#!/usr/bin/env bash
# The test command: every unit, shader, GPU and UI test, the headless `shot` of the city and
# the window smoke test (under xvfb-run when there is no display).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/env.sh
if [ -z "${DISPLAY:-}" ] && [ -z "${WAYLAND_DISPLAY:-}" ] && command -v xvfb-run >/dev/null 2>&1; then
    exec xvfb-run -a -s "-screen 0 1600x1000x24" cargo test --workspace --locked "$@"
fi
exec cargo test --workspace --locked "$@"
