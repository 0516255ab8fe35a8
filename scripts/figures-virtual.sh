#!/usr/bin/env bash
# Regenerates the virtual maps' figures in screenshots/: the goals' run along the city's
# streets (a single map of 8192, four cascades of 2048, the virtual maps with the cache on and
# off, in one run each), still, with every car driving, and with a sun that turns 0.5 degree
# a second, and with every car driving past a still camera (the page view's); the corridor's
# point light and the hall's first spot light against shadow volumes; each run's table (.txt)
# and rows (.csv); and the page views. Minutes each on a software adapter.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/env.sh
cargo build --release --quiet
out=screenshots
bench() {
    local name=$1
    shift
    ./target/release/shadowlab bench builtin:city --sweep virtual --size 640x360 \
        --methods none --frames 30 --warmup 2 --passes --csv "$out/virtual-$name.csv" "$@" \
        > "$out/virtual-$name.txt"
}
bench still
bench cars --animate
bench moving-sun --moving-sun 0.5
bench cars-still --animate --path scripts/paths/city-street-still.csv
# Every car driving with static casters apart at slower paces of the path (pages drawn whole
# and refreshed against resident, the goal's 25%).
for frames in 120 480; do
    ./target/release/shadowlab bench builtin:city --shadow virtual --separate-static on \
        --pages 512 --animate --frames "$frames" --warmup 2 --no-truth --methods none \
        --size 640x360 --csv "$out/virtual-cars-apart-$frames.csv" > /dev/null
done
# The whole street path at 15 m/s (the window's pace, 0.5 m a frame): the still sun, every
# car driving with static casters apart, and with one layer per page.
paced="--shadow virtual --speed 15 --frames 2790 --warmup 2 --no-truth --methods none --size 640x360"
./target/release/shadowlab bench builtin:city $paced \
    --csv "$out/virtual-still-15.csv" > "$out/virtual-still-15.txt"
./target/release/shadowlab bench builtin:city $paced --separate-static on --pages 512 --animate \
    --csv "$out/virtual-cars-apart-15.csv" > "$out/virtual-cars-apart-15.txt"
./target/release/shadowlab bench builtin:city $paced --animate \
    --csv "$out/virtual-cars-one-15.csv" > "$out/virtual-cars-one-15.txt"
# The per-page oracle: pairs drawn against pairs needed, where every page is drawn (the
# cache off), without and with the receiver mask, on the street path and the corridor.
for mask in off on; do
    ./target/release/shadowlab bench builtin:city --shadow virtual --cache off \
        --receiver-mask "$mask" --frames 30 --warmup 2 --no-truth --methods none \
        --size 640x360 --csv "$out/virtual-oracle-city-mask-$mask.csv" > /dev/null
    ./target/release/shadowlab bench builtin:corridor --light point --shadow virtual \
        --cache off --receiver-mask "$mask" --frames 30 --warmup 2 --no-truth --methods none \
        --size 640x360 --csv "$out/virtual-oracle-corridor-mask-$mask.csv" > /dev/null
done
# The corridor's point light, its cube of pages against shadow volumes (exact).
./target/release/shadowlab bench builtin:corridor --light point --sweep virtual --size 640x360 \
    --methods none --frames 30 --warmup 2 --passes --csv "$out/virtual-point-corridor.csv" \
    > "$out/virtual-point-corridor.txt"
# The same with faces of 4096 (the six coarsest mips, a level each).
./target/release/shadowlab bench builtin:corridor --light point --sweep virtual --levels 6 \
    --size 640x360 --methods none --frames 30 --warmup 2 --passes \
    --csv "$out/virtual-point-corridor-4096.csv" > "$out/virtual-point-corridor-4096.txt"
./target/release/shadowlab shot builtin:corridor --light point --shadow virtual --size 1280x720 \
    --eye=-30,2.5,-3 --target=-5,2,2 --overlay light-view \
    --out "$out/virtual-point-pages.png" --stats "$out/virtual-point-pages.json"
# The hall's first spot light (aimed at the statue): one chain of pages along its cone,
# against shadow volumes (exact), along the walk round the statue.
./target/release/shadowlab bench builtin:hall --light spot --sweep virtual --size 640x360 \
    --methods none --frames 30 --warmup 2 --passes --csv "$out/virtual-spot-hall.csv" \
    > "$out/virtual-spot-hall.txt"
./target/release/shadowlab shot builtin:hall --light spot --shadow virtual --size 1280x720 \
    --eye=-1,8,9 --target=-2,0,0 --overlay light-view \
    --out "$out/virtual-spot-pages.png" --stats "$out/virtual-spot-pages.json"
./target/release/shadowlab shot builtin:city --shadow virtual --size 1280x720 \
    --eye=-330,3.5,8 --target=-200,12,8 --overlay light-view \
    --out "$out/virtual-pages.png" --stats "$out/virtual-pages.json"
