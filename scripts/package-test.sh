#!/usr/bin/env bash
# Package test: installs the main build (VKGI_BUILD_DIR, default build/, already built) into a
# temporary prefix, moves the prefix (the package must be relocatable), builds tests/package
# against it with find_package(vkgi), and runs its tests: the embedding example renders the
# Cornell box on its own device and matches vkgi-render's image of the same view. Finally the
# example is installed into the moved prefix and run from there without VKGI_SPIRV_DIR, so the
# library finds its SPIR-V relative to the binary. Prints the install size and the time taken.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${VKGI_BUILD_DIR:-$root/build}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
start=$(date +%s.%N)
lvp=/usr/share/vulkan/icd.d/lvp_icd.x86_64.json
if [[ -z "${VK_DRIVER_FILES:-}" && -f "$lvp" ]]; then
    export VK_DRIVER_FILES="$lvp"
fi
export MESA_SHADER_CACHE_DIR="$build/mesa-shader-cache"

cmake --install "$build" --prefix "$work/staging" >/dev/null
mv "$work/staging" "$work/prefix"
prefix="$work/prefix"
if grep -rqs -- "$build" "$prefix/lib/cmake" "$prefix/include"; then
    echo "package-test: the installed CMake files or headers mention the build tree $build" >&2
    exit 1
fi
echo "package-test: installed size $(du -sh "$prefix" | cut -f1) ($(find "$prefix" -name '*.spv' | wc -l) SPIR-V files," \
    "$(find "$prefix/include" -name '*.hpp' | wc -l) headers)"

scene=cornell technique=vpl size=64x64
"$build/apps/vkgi-render" --scene $scene --technique $technique --size $size --out "$work/reference.exr" >/dev/null
cmake -S "$root/tests/package" -B "$work/consumer" -G Ninja -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_PREFIX_PATH="$prefix" -DVKGI_REFERENCE_EXR="$work/reference.exr" \
    -DVKGI_PACKAGE_SCENE=$scene -DVKGI_PACKAGE_TECHNIQUE=$technique -DVKGI_PACKAGE_SIZE=$size >/dev/null
cmake --build "$work/consumer" -j "$(nproc)" | tail -n 20
ctest --test-dir "$work/consumer" --output-on-failure

cmake --install "$work/consumer" --prefix "$prefix" >/dev/null
(cd "$work" && env -u VKGI_SPIRV_DIR "$prefix/bin/vkgi-embed" --scene $scene --technique none --size 16x16 --out "$work/installed.png")
awk -v s="$start" -v e="$(date +%s.%N)" 'BEGIN { printf "package-test: %.1f s\n", e - s }'
