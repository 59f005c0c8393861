// Whether two films of the same scene agree within their Monte Carlo noise, pixel by pixel, for
// renders that should differ only in the last bits of some hit points (two traversal backends,
// two traversal modes): their paths diverge slowly, so the films are compared against the
// standard deviation of the difference that their own variances predict.
#pragma once

#include <cmath>

#include "film/film.h"

namespace penumbra::testing {

struct FilmComparison {
    int identicalPixels = 0;
    int outlierChannels = 0;  // beyond five standard deviations of the difference
    double meanA = 0.0, meanB = 0.0;
};

inline FilmComparison compareWithinNoise(const Film& a, const Film& b) {
    FilmComparison result;
    for (int y = 0; y < a.height(); ++y)
        for (int x = 0; x < a.width(); ++x) {
            const PixelSums& pa = a.at(x, y);
            const PixelSums& pb = b.at(x, y);
            if (pa == pb) ++result.identicalPixels;
            const Rgb ma = pa.mean(), mb = pb.mean(), va = pa.varianceOfMean(), vb = pb.varianceOfMean();
            for (int c = 0; c < 3; ++c) {
                result.meanA += ma[c];
                result.meanB += mb[c];
                // A little is added to sigma for pixels whose samples all agree (zero variance).
                const double sigma = std::sqrt(double(va[c]) + double(vb[c])) + 1e-4 * (ma[c] + mb[c]) + 1e-6;
                if (std::abs(double(ma[c]) - double(mb[c])) > 5.0 * sigma) ++result.outlierChannels;
            }
        }
    const double channels = 3.0 * a.width() * a.height();
    result.meanA /= channels;
    result.meanB /= channels;
    return result;
}

}  // namespace penumbra::testing
