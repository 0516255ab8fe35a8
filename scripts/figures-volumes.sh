#!/usr/bin/env bash
# Regenerates the shadow volumes' goal figures in screenshots/: standard volumes against every
# clamping, with and without culling, along both of Lloyd's scenes' paths (the corridor under
# the sun and under its point lamp, the robot crowd), against the exact shadow; and discrete
# clamping's slices from 1 to 32 against standard volumes (Lloyd's Figure 9, also drawn as
# volumes-slices.png). Each run's table (.txt) and rows (.csv).
# SIZE (default 640x360; the GPU tables in README.md are 1280x720), FRAMES (default 8) and OUT
# (default screenshots) choose the runs. Minutes each on a software adapter.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/env.sh
cargo build --release --quiet
out=${OUT:-screenshots}
size=${SIZE:-640x360}
frames=${FRAMES:-8}
sweep() {
    local name=$1 scene=$2
    shift 2
    ./target/release/shadowlab bench "$scene" --shadow volumes --overlay fill --sweep clamp \
        --methods none,bvol --baseline none --size "$size" --frames "$frames" --warmup 2 \
        --passes --csv "$out/volumes-$name.csv" "$@" > "$out/volumes-$name.txt"
}
sweep corridor-sun builtin:corridor
sweep corridor-lamp builtin:corridor --light point
sweep robots builtin:robots
./target/release/shadowlab bench builtin:corridor --shadow volumes --overlay fill --sweep slices \
    --volume-clamp conservative --methods none,bvol --baseline none --size "$size" \
    --frames "$frames" --warmup 2 --passes --no-truth --csv "$out/volumes-slices.csv" \
    --plot "$out/volumes-slices.png" > "$out/volumes-slices.txt"
