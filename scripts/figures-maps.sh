#!/usr/bin/env bash
# Regenerates many lights' figures (Rákos, GPU Pro 4, ch. 19) in screenshots/: each sweep's
# table (.txt), rows (.csv) and plot (.png). Each takes minutes on a software adapter.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/env.sh
cargo build --release --quiet
out=screenshots
bench() {
    local name=$1
    shift
    ./target/release/shadowlab bench "$@" --sweep maps --size 640x360 --method vfc \
        --frames 4 --warmup 2 --csv "$out/maps-$name.csv" --plot "$out/maps-$name.png" \
        > "$out/maps-$name.txt"
}
hall="builtin:hall --layered-paths traditional,atlas"
# Figure 19.3: 1 to 32 lights (1 to 72 maps) at three map sizes, culling off and on.
bench sizes $hall --light-counts 1,2,4,8,16,32 --map-sizes 256,512,1024
# Figure 19.4: the geometry alone, nothing rasterised.
bench no-raster $hall --light-counts 1,4,8,16,32 --shadow-res 512 --no-raster
# Figure 19.6: a heavier vertex stage.
bench vertex-work $hall --light-counts 1,4,8,16,32 --shadow-res 512 --vertex-work 32
# Figure 19.7: the scene four times.
bench copies $hall --light-counts 1,4,8,16,32 --shadow-res 512 --copies 4
# Figures 19.8 and 19.9: each culling.
bench culling $hall --light-counts 1,4,8,16,32 --shadow-res 512 \
    --layer-cullings none,frustum,back-faces,both
# The city at dusk: the sun's four cascades and up to 48 street lamps by the same path.
bench dusk builtin:city-night --layered-paths traditional,atlas --light-counts 1,4,8,16,48 \
    --shadow-res 512 --sun-cascades
