#include "film/film_merge.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstdio>

#include "core/error.h"
#include "film/adaptive_film.h"

namespace penumbra {

namespace {

PixelWindow windowOf(const FilmFile& f) {
    return f.metadata.crop.value_or(PixelWindow{0, f.film.width(), 0, f.film.height()});
}

// Throws when `part` was not rendered like `first` (the metadata that decides the samples).
void checkSameRender(int width, int height, const FilmMerger::Seen& first, const FilmFile& part,
                     const std::string& name) {
    const std::string& firstName = first.name;
    const RenderMetadata &a = first.metadata, &b = part.metadata;
    auto mismatch = [&](const char* what, const std::string& va, const std::string& vb) {
        throw InputError(
            fmt::format("cannot merge {} and {}: they were rendered with different {} ({} and {})", firstName,
                        name, what, va, vb));
    };
    if (width != part.film.width() || height != part.film.height())
        mismatch("resolutions", fmt::format("{}x{}", width, height),
                 fmt::format("{}x{}", part.film.width(), part.film.height()));
    if (a.sceneHash != b.sceneHash)
        mismatch("scenes", fmt::format("'{}' {}", a.sceneFile, a.sceneHash),
                 fmt::format("'{}' {}", b.sceneFile, b.sceneHash));
    if (a.seed != b.seed) mismatch("seeds", std::to_string(a.seed), std::to_string(b.seed));
    if (a.sampler != b.sampler) mismatch("samplers", a.sampler, b.sampler);
    if (a.accelerator != b.accelerator)
        mismatch("traversal backends (--accel)", a.accelerator, b.accelerator);
}

}  // namespace

std::string describeWindow(const PixelWindow& w) {
    return fmt::format("{},{},{},{}", w.x0, w.x1, w.y0, w.y1);
}

std::string describeRange(const RenderMetadata& m) {
    return fmt::format("[{}, {})", m.firstSample, m.endSample);
}

void FilmMerger::add(FilmFile part, const std::string& name) {
    if (merged_) checkSameRender(merged_->film.width(), merged_->film.height(), first_, part, name);
    // An adaptive render's pixels stop where the whole film (all its samples, all its pixels'
    // neighbours) says so: parts of one would not add up to the film of one render.
    if (part.metadata.adaptive)
        throw InputError(fmt::format(
            "cannot merge {}: it is an adaptive render (penumbra:adaptive {}), whose pixels stop where the "
            "whole "
            "film decides; render it as one job instead (checkpoints and --resume continue it exactly)",
            name, formatAdaptiveAttribute(*part.metadata.adaptive)));
    // Two parts overlap when they share pixels and sample indices: those samples would count twice.
    const PixelWindow window = windowOf(part);
    for (const Seen& earlier : seen_) {
        const RenderMetadata &a = earlier.metadata, &b = part.metadata;
        const bool samplesOverlap = a.firstSample < b.endSample && b.firstSample < a.endSample;
        if (samplesOverlap && earlier.window.intersects(window))
            throw InputError(
                fmt::format("cannot merge {} and {}: their sample ranges {} and {} overlap on shared pixels "
                            "(windows {} and {}); "
                            "each sample of a pixel must come from one part",
                            earlier.name, name, describeRange(a), describeRange(b),
                            describeWindow(earlier.window), describeWindow(window)));
    }
    seen_.push_back(Seen{part.metadata, window, name});
    if (!merged_) {
        first_ = Seen{part.metadata, window, name};
        merged_ = std::move(part);  // zero + the first part's sums, exactly
        return;
    }
    try {
        merged_->film.merge(part.film);
    } catch (const InputError& e) {
        throw InputError(fmt::format("cannot merge {}: {}", name, e.message()));
    }
}

MergeResult FilmMerger::finish() {
    if (!merged_) throw InputError("merge: no films to merge");
    MergeResult result{std::move(*merged_), true, {}};
    merged_.reset();
    RenderMetadata& m = result.merged.metadata;
    m.renderSeconds = 0;
    PixelWindow box = seen_.front().window;
    uint32_t first = seen_.front().metadata.firstSample, end = seen_.front().metadata.endSample;
    for (const Seen& part : seen_) {
        m.renderSeconds += part.metadata.renderSeconds;
        const PixelWindow& w = part.window;
        box = {std::min(box.x0, w.x0), std::max(box.x1, w.x1), std::min(box.y0, w.y0),
               std::max(box.y1, w.y1)};
        first = std::min(first, part.metadata.firstSample);
        end = std::max(end, part.metadata.endSample);
    }

    // Does every pixel of the bounding box get the same contiguous range of samples? The parts'
    // window edges cut the box into cells whose pixels all lie in the same parts, so one pixel per
    // cell answers for the cell (in raster order, so the first bad cell holds the first bad pixel).
    std::vector<int> xs{box.x0, box.x1}, ys{box.y0, box.y1};
    for (const Seen& part : seen_) {
        xs.insert(xs.end(), {part.window.x0, part.window.x1});
        ys.insert(ys.end(), {part.window.y0, part.window.y1});
    }
    for (std::vector<int>* edges : {&xs, &ys}) {
        std::sort(edges->begin(), edges->end());
        edges->erase(std::unique(edges->begin(), edges->end()), edges->end());
    }
    std::vector<std::pair<uint32_t, uint32_t>> ranges;
    std::optional<std::pair<uint32_t, uint32_t>> common;
    for (size_t j = 0; j + 1 < ys.size() && result.uniform; ++j)
        for (size_t i = 0; i + 1 < xs.size() && result.uniform; ++i) {
            const int x = xs[i], y = ys[j];
            if (!box.contains(x, y)) continue;
            ranges.clear();
            for (const Seen& part : seen_)
                if (part.window.contains(x, y) && part.metadata.endSample > part.metadata.firstSample)
                    ranges.emplace_back(part.metadata.firstSample, part.metadata.endSample);
            std::sort(ranges.begin(), ranges.end());
            bool contiguous = !ranges.empty();
            for (size_t k = 1; k < ranges.size(); ++k) contiguous &= ranges[k].first == ranges[k - 1].second;
            if (!contiguous) {
                result.uniform = false;
                result.note =
                    ranges.empty()
                        ? fmt::format("pixel ({}, {}) lies in no part, though inside the merged window {}", x,
                                      y, describeWindow(box))
                        : fmt::format("the sample ranges of pixel ({}, {}) leave a gap", x, y);
                break;
            }
            const std::pair<uint32_t, uint32_t> span{ranges.front().first, ranges.back().second};
            if (!common)
                common = span;
            else if (*common != span) {
                result.uniform = false;
                result.note =
                    fmt::format("pixel ({}, {}) holds samples [{}, {}) but pixel ({}, {}) [{}, {})", box.x0,
                                box.y0, common->first, common->second, x, y, span.first, span.second);
            }
        }
    if (result.uniform && common) {
        first = common->first;
        end = common->second;
    }
    m.firstSample = first;
    m.endSample = end;
    m.samplesPerPixel = int(end - first);
    m.crop = box == PixelWindow{0, result.merged.film.width(), 0, result.merged.film.height()}
                 ? std::nullopt
                 : std::optional(box);
    seen_.clear();
    return result;
}

MergeResult mergeFilms(const std::vector<FilmFile>& parts, const std::vector<std::string>& names) {
    FilmMerger merger;
    for (size_t i = 0; i < parts.size(); ++i) merger.add(parts[i], names[i]);
    return merger.finish();
}

MergeResult mergeFilmFiles(const std::vector<std::filesystem::path>& paths) {
    FilmMerger merger;
    for (const auto& path : paths) merger.add(readFilmExr(path), path.string());
    return merger.finish();
}

void checkResumable(const FilmFile& file, const std::string& path, const ResumeTarget& target) {
    const RenderMetadata& m = file.metadata;
    auto fail = [&](const std::string& message) {
        SourceLocation where;
        where.file = path;
        throw InputError(where, "cannot resume this film: " + message);
    };
    if (m.sceneHash != target.sceneHash)
        fail(fmt::format(
            "it was rendered from a different scene ('{}' hashing to {}; the scene file now hashes to {})",
            m.sceneFile, m.sceneHash, target.sceneHash));
    if (file.film.width() != target.width || file.film.height() != target.height)
        fail(fmt::format("it is {}x{}, the render {}x{} (pass --res {}x{})", file.film.width(),
                         file.film.height(), target.width, target.height, file.film.width(),
                         file.film.height()));
    if (m.seed != target.seed)
        fail(fmt::format("it was rendered with seed {}, not {} (pass --seed {})", m.seed, target.seed,
                         m.seed));
    if (m.sampler != target.sampler)
        fail(fmt::format("it was rendered with the {} sampler, not {} (pass --sampler {})", m.sampler,
                         target.sampler, m.sampler));
    if (m.accelerator != target.accelerator)
        fail(fmt::format("it was rendered with --accel {}, not {}", m.accelerator, target.accelerator));
    const PixelWindow full{0, target.width, 0, target.height};
    const PixelWindow fileWindow = m.crop.value_or(full), targetWindow = target.crop.value_or(full);
    if (fileWindow != targetWindow)
        fail(fmt::format("it covers the pixels {}, the render {} (pass --crop {})",
                         describeWindow(fileWindow), describeWindow(targetWindow),
                         describeWindow(fileWindow)));
    auto describeAdaptive = [](const std::optional<AdaptiveSettings>& a) {
        return a ? fmt::format("adaptive sampling {} ([absolute:]THRESHOLD:MIN_SPP)",
                               formatAdaptiveAttribute(*a))
                 : std::string("no adaptive sampling");
    };
    if (m.adaptive != target.adaptive)
        fail(fmt::format(
            "it was rendered with {}, the render asks for {} (pass the same --adaptive and --min-spp)",
            describeAdaptive(m.adaptive), describeAdaptive(target.adaptive)));
    const uint32_t count = m.endSample - m.firstSample;
    if (m.adaptive) {
        // Each pixel of the window stopped at a decision point or holds every sample.
        if (m.firstSample != 0)
            fail(fmt::format("an adaptive film starts at sample 0, not {}", m.firstSample));
        for (int y = 0; y < target.height; ++y)
            for (int x = 0; x < target.width; ++x) {
                const uint32_t held = file.film.at(x, y).sampleCount;
                const bool possible =
                    fileWindow.contains(x, y) ? adaptiveCountPossible(*m.adaptive, held, count) : held == 0;
                if (!possible)
                    fail(fmt::format(
                        "pixel ({}, {}) holds {} samples, which an adaptive render ({}) of samples {} "
                        "does not leave",
                        x, y, held, describeAdaptive(m.adaptive), describeRange(m)));
            }
    }
    for (int y = 0; y < target.height && !m.adaptive; ++y)
        for (int x = 0; x < target.width; ++x) {
            const uint32_t expected = fileWindow.contains(x, y) ? count : 0;
            if (file.film.at(x, y).sampleCount != expected)
                fail(fmt::format(
                    "pixel ({}, {}) holds {} samples where its samples {} say {} (a merge of parts that "
                    "do not cover the same samples everywhere?)",
                    x, y, file.film.at(x, y).sampleCount, describeRange(m), expected));
        }
    if (target.firstSample && m.firstSample != *target.firstSample)
        fail(fmt::format("it holds samples {}, the render starts at sample {} (--samples)", describeRange(m),
                         *target.firstSample));
    if (m.endSample > target.endSample)
        fail(fmt::format("it already holds samples {}, beyond --spp {}", describeRange(m), target.endSample));
}

}  // namespace penumbra
