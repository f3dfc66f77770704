// compare_exr A.exr B.exr [tolerance]: exits 0 when both images are finite, the same size, and
// their channel means agree within `tolerance` relative (default 1e-5) and no pixel differs by
// more than 1e-3 nits + 1e-3 relative; prints the means and the largest pixel difference.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "vkgi/image_io.hpp"

int main(int argc, char** argv) {
    if (argc < 3 || argc > 4) {
        std::fprintf(stderr, "usage: compare_exr A.exr B.exr [tolerance]\n");
        return 2;
    }
    double tolerance = argc == 4 ? std::atof(argv[3]) : 1e-5;
    auto a = vkgi::readExr(argv[1]);
    auto b = vkgi::readExr(argv[2]);
    if (!a || !b) {
        std::fprintf(stderr, "compare_exr: %s\n", (a ? b.error() : a.error()).message.c_str());
        return 1;
    }
    if (a->width != b->width || a->height != b->height || a->pixels.empty()) {
        std::fprintf(stderr, "compare_exr: sizes differ (%ux%u vs %ux%u)\n", a->width, a->height, b->width, b->height);
        return 1;
    }
    double meanA[3] = {}, meanB[3] = {}, maxDiff = 0.0;
    bool finite = true, pixelsClose = true;
    for (size_t i = 0; i < a->pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            double x = a->pixels[i][c], y = b->pixels[i][c];
            finite = finite && std::isfinite(x) && std::isfinite(y);
            meanA[c] += x;
            meanB[c] += y;
            double d = std::abs(x - y);
            maxDiff = std::max(maxDiff, d);
            pixelsClose = pixelsClose && d <= 1e-3 + 1e-3 * std::abs(y);
        }
    bool meansClose = true;
    for (int c = 0; c < 3; ++c) {
        meanA[c] /= double(a->pixels.size());
        meanB[c] /= double(b->pixels.size());
        meansClose = meansClose && std::abs(meanA[c] - meanB[c]) <= tolerance * std::max(std::abs(meanB[c]), 1e-6);
    }
    std::printf("mean A %.6f %.6f %.6f  B %.6f %.6f %.6f  max pixel difference %.3g\n", meanA[0], meanA[1], meanA[2],
                meanB[0], meanB[1], meanB[2], maxDiff);
    bool positive = meanB[0] > 0.0 && meanB[1] > 0.0 && meanB[2] > 0.0;
    if (!finite || !positive || !meansClose || !pixelsClose) {
        std::fprintf(stderr, "compare_exr: images differ (finite %d, positive %d, means %d, pixels %d)\n", finite,
                     positive, meansClose, pixelsClose);
        return 1;
    }
    return 0;
}
