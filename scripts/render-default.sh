#!/usr/bin/env bash
# One command from a fresh checkout to a picture: installs the Debian packages (if missing),
# builds, and renders the built-in Cornell box at 256x256 with global illumination (VPL: the
# Cornell light is a spotlight; the default 256 VPLs interleaved over 4x4 tiles, gathered at half
# resolution + refine) to out/cornell.png and out/cornell.exr, printing the per-pass GPU times.
# Extra arguments go to vkgi-render and win over these (e.g. --technique vct --compare).
# VKGI_DEVICE=<name substring> picks the Vulkan device (lavapipe: VKGI_DEVICE=llvmpipe).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$root/scripts/install-deps.sh"
bash "$root/scripts/build.sh"
build="${VKGI_BUILD_DIR:-$root/build}"
cd "$root"
"$build/apps/vkgi-render" --scene cornell --technique vpl --vpl.lowres 2 --size 256x256 \
    --out out/cornell.png --out out/cornell.exr "$@"
