#!/usr/bin/env bash
# ASan + UBSan build (clang) of the whole project: runs the unit, GPU and stability suites under the
# sanitizers, then fuzzes the glTF loader for FUZZ_SECONDS (default 60) from the committed corpus
# (tests/assets/gltf/bad and the fuzzer-grown tests/assets/gltf/fuzz); the last lines give its coverage.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$root/scripts/install-deps.sh"
build="${VKGI_ASAN_BUILD_DIR:-$root/build-asan}"
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_C_COMPILER=clang \
    -DCMAKE_CXX_COMPILER=clang++ -DGI_SANITIZE=ON -DGI_FUZZ=ON -DGI_BUILD_APPS=OFF >/dev/null
cmake --build "$build" -j "$(nproc)"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
# Unit tests: full leak checking. GPU tests: leak checking off, because lavapipe's JIT-compiled
# shader code allocates from anonymous code pages that LeakSanitizer cannot attribute or
# suppress; leaked Vulkan objects are caught there by the validation layer's object tracker.
(cd "$build" && ASAN_OPTIONS="detect_leaks=1:abort_on_error=1" ctest --output-on-failure -j "$(nproc)" -L unit)
(cd "$build" && ASAN_OPTIONS="detect_leaks=0:abort_on_error=1" ctest --output-on-failure -j "$(nproc)" -L "gpu|stability")
corpus="$build/fuzz-corpus"
mkdir -p "$corpus"
cp "$root"/tests/assets/gltf/*/*.gl* "$corpus"/ 2>/dev/null || true
ASAN_OPTIONS="detect_leaks=1" "$build/tests/vkgi_gltf_fuzz" -max_total_time="${FUZZ_SECONDS:-60}" -max_len=65536 -timeout=10 \
    -print_final_stats=1 "$corpus" 2>&1 | tail -n 15
