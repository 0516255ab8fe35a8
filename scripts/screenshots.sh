#!/usr/bin/env bash
# Regenerates the pictures in screenshots/ that README.md shows. Headless, on any adapter.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/env.sh
run() { cargo run --release --quiet -- "$@"; }
run shot builtin:city --size 1280x720 --shadow-res 2048 \
    --eye=-250,90,160 --target=-90,0,40 --overlay light-view \
    --out screenshots/city.png --stats screenshots/city.json
run shot builtin:city --size 1280x720 --shadow-res 2048 \
    --eye=-330,3.5,8 --target=-200,12,8 \
    --out screenshots/city-street.png --stats screenshots/city-street.json
run shot builtin:city --size 1280x720 --shadow-res 2048 \
    --eye=-330,30,8 --target=-220,4,20 --method frag --overlay light-view --overlay casters \
    --out screenshots/city-frag-casters.png --stats screenshots/city-frag-casters.json
run shot builtin:city --size 1280x720 --shadow-res 2048 \
    --eye=-330,3.5,8 --target=-200,12,8 --shadow cascades --method frag --overlay cascades \
    --out screenshots/city-cascades.png --stats screenshots/city-cascades.json
run shot builtin:city --size 1280x720 --shadow-res 2048 \
    --eye=-330,3.5,8 --target=-200,12,8 --shadow cascades --method frag --overlay cascades \
    --observe-from=-560,260,260 --observe-target=-250,0,0 \
    --out screenshots/city-observer.png --stats screenshots/city-observer.json
run shot builtin:city --size 1280x720 --shadow-res 2048 \
    --eye=-330,3.5,8 --target=-200,12,8 --shadow lispsm --method frag \
    --out screenshots/city-lispsm.png --stats screenshots/city-lispsm.json
run shot builtin:city --size 1280x720 \
    --eye=-330,3.5,8 --target=-200,12,8 --shadow volumes --method none --volume-clamp none \
    --overlay fill --out screenshots/city-fill-standard.png --stats screenshots/city-fill-standard.json
run shot builtin:city --size 1280x720 \
    --eye=-330,3.5,8 --target=-200,12,8 --shadow volumes --method bvol --volume-clamp continuous \
    --overlay fill --out screenshots/city-fill-cc.png --stats screenshots/city-fill-cc.json
run shot builtin:corridor --light point --size 1280x720 \
    --eye=-30,1.7,-3.5 --target=-10,1,2 --shadow volumes --method bvol \
    --out screenshots/corridor.png --stats screenshots/corridor.json
run shot builtin:corridor --light point --size 1280x720 \
    --eye=-30,1.7,-3.5 --target=-10,1,2 --shadow volumes --method none --volume-clamp none \
    --overlay fill --out screenshots/corridor-fill-standard.png --stats screenshots/corridor-fill-standard.json
run shot builtin:corridor --light point --size 1280x720 \
    --eye=-30,1.7,-3.5 --target=-10,1,2 --shadow volumes --method bvol --volume-clamp continuous \
    --overlay fill --out screenshots/corridor-fill-cc.png --stats screenshots/corridor-fill-cc.json
run shot builtin:corridor --light point --size 1280x720 \
    --eye=-30,1.7,-3.5 --target=-10,1,2 --shadow volumes --method bvol --volume-clamp conservative \
    --overlay fill --out screenshots/corridor-fill-strips.png --stats screenshots/corridor-fill-strips.json
run shot builtin:hall --lights 16 --layered atlas --size 1280x720 --shadow-res 1024 \
    --eye=9,3.2,5 --target=0,1.6,0 --out screenshots/hall-lights.png --stats screenshots/hall-lights.json
run shot builtin:robots --size 1280x720 \
    --eye=-28,1.7,0 --target=0,1.7,-3 --shadow volumes --method bvol --overlay volumes \
    --out screenshots/robots-volumes.png --stats screenshots/robots-volumes.json
if command -v xvfb-run >/dev/null 2>&1 || [ -n "${DISPLAY:-}" ]; then
    wrap=(); [ -z "${DISPLAY:-}" ] && wrap=(xvfb-run -a -s "-screen 0 1600x1000x24")
    shots=$(mktemp -d)
    # A config folder of its own: the picture starts from the defaults and the user's
    # remembered settings stay untouched.
    SHADOWLAB_CONFIG_DIR="$shots/config" "${wrap[@]}" cargo run --release --quiet -- \
        builtin:city --eye=-250,90,160 --target=-90,0,40 --overlay light-view \
        --exit-after-frames 8 --screenshot-dir "$shots"
    mv "$shots"/*.png screenshots/window.png
    # The city of 100,000 objects flown along its streets, a line per frame: where each
    # frame's time went and whether it waited for the GPU.
    SHADOWLAB_CONFIG_DIR="$shots/config" "${wrap[@]}" cargo run --release --quiet -- \
        builtin:city:50 --fresh --play-path --exit-after-frames 30 \
        --frame-log screenshots/window-city-100k-frames.csv --screenshot-dir "$shots"
    mv "$shots"/*.png screenshots/window-city-100k.png
    rm -rf "$shots"
fi
