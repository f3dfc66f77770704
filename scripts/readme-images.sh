#!/usr/bin/env bash
# Regenerates the README's pictures (docs/images): for each built-in scene the path-traced
# reference (all bounces) and the rasterised direct light, both 192x192 PNG with the default
# tone map. The reference uses SPP (default 256) paths per pixel.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${VKGI_BUILD_DIR:-$root/build}"
out="$root/docs/images"
mkdir -p "$out"
# scene:exposure — the sun-lit scenes (1e4 lux, ~1e3 nits on lit floors) need a lower exposure.
for entry in cornell:1 cornell_spot:1 cornell_emissive:1 room:0.002 bunny_box:1 atrium:0.002; do
    scene="${entry%%:*}" exposure="${entry##*:}"
    "$build/apps/vkgi-render" --scene "$scene" --technique reference --spp "${SPP:-256}" --size 192x192 \
        --exposure "$exposure" --out "$out/$scene-reference.png" >/dev/null
    "$build/apps/vkgi-render" --scene "$scene" --technique none --size 192x192 --exposure "$exposure" \
        --out "$out/$scene-direct.png" >/dev/null
    echo "wrote $out/$scene-{reference,direct}.png"
done
