#!/usr/bin/env bash
# The test command. With no tier, every test of the workspace in one `cargo test`; with a tier,
# that tier alone (README.md, Tests):
#   fast        CPU unit tests and the naga validation of every composed shader: no adapter
#   gpu         the headless GPU tests of whole frames (`tests/tests/gpu/`) and the panel's
#               egui_kittest tests, on whatever adapter wgpu finds
#   end-to-end  the tests that run the `shadowlab` binary (`app/tests/end_to_end/`): the CLI,
#               its files and exit codes, the window (under xvfb-run when there is no display)
# Further arguments go to `cargo test` (a test name filters).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/env.sh
tier=all
case "${1:-}" in
    fast | gpu | end-to-end | all) tier=$1; shift ;;
esac
case "$tier" in
    fast) targets=(-p render-core -p shadowlab --lib --bins) ;;
    gpu) targets=(-p shadowlab-tests -p ui) ;;
    end-to-end) targets=(-p shadowlab --test end_to_end) ;;
    all) targets=(--workspace) ;;
esac
if [ "$tier" != fast ] && [ -z "${DISPLAY:-}" ] && [ -z "${WAYLAND_DISPLAY:-}" ] \
    && command -v xvfb-run >/dev/null 2>&1; then
    exec xvfb-run -a -s "-screen 0 1600x1000x24" cargo test --locked "${targets[@]}" "$@"
fi
exec cargo test --locked "${targets[@]}" "$@"
