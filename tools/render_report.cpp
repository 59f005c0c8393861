#include "tools/render_report.h"

#include <fmt/format.h>

#include <cstdio>

namespace penumbra {

namespace {

std::string samplesText(const RenderDescription& d, uint32_t end) {
    std::string text = fmt::format("samples {}:{} ({} spp", d.firstSample, end, end - d.firstSample);
    if (d.filmFirstSample) text += fmt::format("; the film then holds {}:{}", *d.filmFirstSample, end);
    return text + ")";
}

std::string formatDuration(double seconds) {
    if (seconds < 60) return fmt::format("{:.1f} s", seconds);
    const long s = long(seconds + 0.5);
    if (s < 3600) return fmt::format("{}m{:02d}s", s / 60, int(s % 60));
    return fmt::format("{}h{:02d}m", s / 3600, int(s / 60 % 60));
}

}  // namespace

std::string describeRender(const RenderDescription& d) {
    std::string text = fmt::format("rendering {}: {}x{}", d.scene, d.width, d.height);
    if (d.crop) text += fmt::format(", pixels {},{},{},{}", d.crop->x0, d.crop->x1, d.crop->y0, d.crop->y1);
    if (!d.resumedFrom.empty()) text += fmt::format(", continuing {}", d.resumedFrom);
    text += fmt::format(", {}, {} sampler, seed {}, {} thread{}, {}, film {}", samplesText(d, d.endSample),
                        d.sampler, d.seed, d.threads, d.threads == 1 ? "" : "s", d.accelerator, d.film);
    return text;
}

std::string describeRendered(const RenderDescription& d, uint32_t endReached, double renderSeconds,
                             double buildSeconds) {
    return fmt::format("rendered {}x{}, {}, {} sampler, seed {}, in {:.2f} s (scene build {:.2f} s)", d.width,
                       d.height, samplesText(d, endReached), d.sampler, d.seed, renderSeconds, buildSeconds);
}

std::string shellWord(const std::string& word) {
    const bool plain = !word.empty() && word.find_first_not_of(
                                            "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                            "0123456789_-+./:,=@%") == std::string::npos;
    if (plain) return word;
    std::string quoted = "'";
    for (char c : word) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return quoted + "'";
}

void ProgressLine::update(size_t done, size_t total) {
    if (!enabled_) return;
    const auto now = Clock::now();
    if (!firstTile_ && done > 0) {
        firstTile_ = now;
        firstDone_ = done;
    }
    if (done != total && now - lastPrint_ < std::chrono::milliseconds(100)) return;
    lastPrint_ = now;
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    const double fraction = total ? double(done) / double(total) : 1.0;
    std::string eta = "ETA estimating";
    const double sinceFirst = std::chrono::duration<double>(now - *firstTile_).count();
    if (done == total)
        eta = "done";
    else if (fraction >= 0.02 && sinceFirst >= 1.0 && done > firstDone_)
        eta = "ETA " + formatDuration(sinceFirst / double(done - firstDone_) * double(total - done));
    constexpr int kWidth = 30;
    const int filled = int(fraction * kWidth);
    std::fprintf(stderr, "\r[%s%s] %5.1f%%  elapsed %s  %-16s", std::string(filled, '=').c_str(),
                 std::string(kWidth - filled, ' ').c_str(), 100.0 * fraction, formatDuration(elapsed).c_str(),
                 eta.c_str());
    if (done == total) std::fprintf(stderr, "\n");
    std::fflush(stderr);
}

}  // namespace penumbra
