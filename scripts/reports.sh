#!/usr/bin/env bash
# Regenerates the reports README.md links: the city's and the courtyard glTF's, each a folder
# of `shadowlab report` (index.html, report.md, rows.csv, rows.json, plots, screenshots), with
# the sweeps of their families; and the hall's many lights with the sweep of their number.
# Small settings, so each takes minutes on a software adapter; a user's own run would use
# more frames and a larger picture.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/env.sh
cargo build --release --quiet
out=screenshots
rm -rf "$out/report-city" "$out/report-courtyard" "$out/report-hall"
./target/release/shadowlab report builtin:city --out "$out/report-city" \
    --size 640x360 --frames 8 --warmup 2
./target/release/shadowlab report assets/scenes/courtyard.gltf \
    --path assets/paths/courtyard-walk.csv --out "$out/report-courtyard" \
    --size 640x360 --frames 8 --warmup 2
./target/release/shadowlab report builtin:hall --families lights --out "$out/report-hall" \
    --size 640x360 --shadow-res 512 --frames 8 --warmup 2
