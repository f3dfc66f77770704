#!/usr/bin/env bash
# Package test: installs the main build (VKGI_BUILD_DIR, default build/, already built) into a
# temporary prefix, moves the prefix (the package must be relocatable), builds tests/package
# against it with find_package(vkgi), and runs its tests: the embedding example renders the
# Cornell box on its own device and matches vkgi-render's image of the same view. The example is
# then installed into the moved prefix and run from another folder (the SPIR-V is inside the
# library: no file is read). Then the core-only host (tests/package/core) is built against the
# package found without components: the core's targets file must name no optional dependency, its
# configure runs with those packages disabled, and the host's link command and ldd must show none
# of them. Prints the install size and the time taken.
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
if [[ -n "$(find "$prefix" -name '*.spv')" || -e "$prefix/share/vkgi" ]]; then
    echo "package-test: the package installs SPIR-V files; the shaders belong inside the library" >&2
    exit 1
fi
# The library embeds the GI shaders and nothing else (test, viewer and bench shaders stay in those
# programs): every embedded array is named vkgi_spirv_gi_<path under shaders/>.
embedded="$(nm --defined-only "$prefix/lib/libvkgi_gi.a" | grep -Eo 'vkgi_spirv_gi_[A-Za-z0-9_]+_(comp|vert|frag|geom)$' | sort -u)"
if [[ -z "$embedded" ]] || grep -Ev '^vkgi_spirv_gi_gi_' <<<"$embedded" | grep -q . ||
    grep -q gather_baseline <<<"$embedded"; then
    echo "package-test: libvkgi_gi.a embeds shaders other than the GI library's own:" >&2
    echo "$embedded" >&2
    exit 1
fi
echo "package-test: installed size $(du -sh "$prefix" | cut -f1) ($(find "$prefix/include" -name '*.hpp' | wc -l) headers," \
    "$(wc -l <<<"$embedded") shaders embedded in libvkgi_gi.a)"

scene=cornell technique=vpl size=64x64
"$build/apps/vkgi-render" --scene $scene --technique $technique --size $size --out "$work/reference.exr" >/dev/null
cmake -S "$root/tests/package" -B "$work/consumer" -G Ninja -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_PREFIX_PATH="$prefix" -DVKGI_REFERENCE_EXR="$work/reference.exr" \
    -DVKGI_PACKAGE_SCENE=$scene -DVKGI_PACKAGE_TECHNIQUE=$technique -DVKGI_PACKAGE_SIZE=$size >/dev/null
cmake --build "$work/consumer" -j "$(nproc)" | tail -n 20
ctest --test-dir "$work/consumer" --output-on-failure

cmake --install "$work/consumer" --prefix "$prefix" >/dev/null
(cd "$work" && "$prefix/bin/vkgi-embed" --scene $scene --technique none --size 16x16 --out "$work/installed.png")

# The core alone. Optional dependencies by the names of their CMake packages/targets and libraries.
optional='embree|TBB::|libtbb|OpenEXR|Imath|TinyGLTF|tinygltf|nlohmann|vkgi::(io|reference|bench|stb)'
if grep -Eq "$optional" "$prefix/lib/cmake/vkgi/vkgiTargets.cmake"; then
    echo "package-test: the core's vkgiTargets.cmake references an optional dependency:" >&2
    grep -En "$optional" "$prefix/lib/cmake/vkgi/vkgiTargets.cmake" >&2
    exit 1
fi
cmake -S "$root/tests/package/core" -B "$work/core" -G Ninja -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_PREFIX_PATH="$prefix" >/dev/null
cmake --build "$work/core" -j "$(nproc)" | tail -n 5
link="$(ninja -C "$work/core" -t commands vkgi-minimal | tail -n 1)"
if grep -Eq "$optional|libvkgi_(io|reference|bench|stb)" <<<"$link"; then
    echo "package-test: the core-only host links an optional part: $link" >&2
    exit 1
fi
if ldd "$work/core/vkgi-minimal" | grep -Eq "$optional"; then
    echo "package-test: the core-only host loads an optional library:" >&2
    ldd "$work/core/vkgi-minimal" >&2
    exit 1
fi
echo "package-test: core-only host links $(grep -Eo 'libvkgi_[a-z]+\.a' <<<"$link" | sort -u | tr '\n' ' ')and loads" \
    "$(ldd "$work/core/vkgi-minimal" | awk '{print $1}' | grep -Ev '^(linux-vdso|/lib64)' | tr '\n' ' ')"
ctest --test-dir "$work/core" --output-on-failure
awk -v s="$start" -v e="$(date +%s.%N)" 'BEGIN { printf "package-test: %.1f s\n", e - s }'
