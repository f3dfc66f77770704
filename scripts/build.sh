#!/usr/bin/env bash
# Configures and builds vkgi into ./build (Release with asserts off, warnings as errors when CI=true).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$root/scripts/install-deps.sh"
build="${VKGI_BUILD_DIR:-$root/build}"
werror=OFF
[ "${CI:-}" = "true" ] && werror=ON
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DGI_WERROR=$werror >/dev/null
cmake --build "$build" -j "$(nproc)"
