#include "film/film_merge.h"

#include <algorithm>
#include <cstdio>

#include <fmt/format.h>

#include "core/error.h"
#include "film/adaptive_film.h"

namespace penumbra {

namespace {

PixelWindow windowOf(const FilmFile& f) {
    return f.metadata.crop.value_or(PixelWindow{0, f.film.width(), 0, f.film.height()});
}

// Throws when `part` was not rendered like `first` (the metadata that decides the samples).
void checkSameRender(const FilmFile& first, const std::string& firstName, const FilmFile& part,
                     const std::string& name) {
    const RenderMetadata &a = first.metadata, &b = part.metadata;
    auto mismatch = [&](const char* what, const std::string& va, const std::string& vb) {
        throw InputError(fmt::format("cannot merge {} and {}: they were rendered with different {} ({} and {})",
                                     firstName, name, what, va, vb));
    };
    if (first.film.width() != part.film.width() || first.film.height() != part.film.height())
        mismatch("resolutions", fmt::format("{}x{}", first.film.width(), first.film.height()),
                 fmt::format("{}x{}", part.film.width(), part.film.height()));
    if (a.sceneHash != b.sceneHash)
        mismatch("scenes", fmt::format("'{}' {}", a.sceneFile, a.sceneHash), fmt::format("'{}' {}", b.sceneFile, b.sceneHash));
    if (a.seed != b.seed) mismatch("seeds", std::to_string(a.seed), std::to_string(b.seed));
    if (a.sampler != b.sampler) mismatch("samplers", a.sampler, b.sampler);
    if (a.accelerator != b.accelerator) mismatch("traversal backends (--accel)", a.accelerator, b.accelerator);
}

}  // namespace

std::string describeWindow(const PixelWindow& w) { return fmt::format("{},{},{},{}", w.x0, w.x1, w.y0, w.y1); }

std::string describeRange(const RenderMetadata& m) { return fmt::format("[{}, {})", m.firstSample, m.endSample); }

MergeResult mergeFilms(const std::vector<FilmFile>& parts, const std::vector<std::string>& names) {
    if (parts.empty()) throw InputError("merge: no films to merge");
    // An adaptive render's pixels stop where the whole film (all its samples, all its pixels'
    // neighbours) says so: parts of one would not add up to the film of one render.
    for (size_t i = 0; i < parts.size(); ++i)
        if (parts[i].metadata.adaptive)
            throw InputError(fmt::format(
                "cannot merge {}: it is an adaptive render (penumbra:adaptive {}), whose pixels stop where the whole "
                "film decides; render it as one job instead (checkpoints and --resume continue it exactly)",
                names[i], formatAdaptiveAttribute(*parts[i].metadata.adaptive)));
    for (size_t i = 1; i < parts.size(); ++i) checkSameRender(parts[0], names[0], parts[i], names[i]);

    // Two parts overlap when they share pixels and sample indices: those samples would count twice.
    for (size_t i = 0; i < parts.size(); ++i)
        for (size_t j = i + 1; j < parts.size(); ++j) {
            const RenderMetadata &a = parts[i].metadata, &b = parts[j].metadata;
            const bool samplesOverlap = a.firstSample < b.endSample && b.firstSample < a.endSample;
            if (samplesOverlap && windowOf(parts[i]).intersects(windowOf(parts[j])))
                throw InputError(fmt::format(
                    "cannot merge {} and {}: their sample ranges {} and {} overlap on shared pixels (windows {} and {}); "
                    "each sample of a pixel must come from one part",
                    names[i], names[j], describeRange(a), describeRange(b), describeWindow(windowOf(parts[i])),
                    describeWindow(windowOf(parts[j]))));
        }

    MergeResult result{FilmFile{Film(parts[0].film.width(), parts[0].film.height()), parts[0].metadata}, true, {}};
    RenderMetadata& m = result.merged.metadata;
    m.renderSeconds = 0;
    PixelWindow box = windowOf(parts[0]);
    uint32_t first = parts[0].metadata.firstSample, end = parts[0].metadata.endSample;
    for (size_t i = 0; i < parts.size(); ++i) {
        const FilmFile& part = parts[i];
        try {
            result.merged.film.merge(part.film);
        } catch (const InputError& e) {
            throw InputError(fmt::format("cannot merge {}: {}", names[i], e.message()));
        }
        m.renderSeconds += part.metadata.renderSeconds;
        const PixelWindow w = windowOf(part);
        box = {std::min(box.x0, w.x0), std::max(box.x1, w.x1), std::min(box.y0, w.y0), std::max(box.y1, w.y1)};
        first = std::min(first, part.metadata.firstSample);
        end = std::max(end, part.metadata.endSample);
    }

    // Does every pixel of the bounding box get the same contiguous range of samples?
    std::vector<std::pair<uint32_t, uint32_t>> ranges;
    std::optional<std::pair<uint32_t, uint32_t>> common;
    for (int y = box.y0; y < box.y1 && result.uniform; ++y)
        for (int x = box.x0; x < box.x1 && result.uniform; ++x) {
            ranges.clear();
            for (const FilmFile& part : parts)
                if (windowOf(part).contains(x, y) && part.metadata.endSample > part.metadata.firstSample)
                    ranges.emplace_back(part.metadata.firstSample, part.metadata.endSample);
            std::sort(ranges.begin(), ranges.end());
            bool contiguous = !ranges.empty();
            for (size_t k = 1; k < ranges.size(); ++k) contiguous &= ranges[k].first == ranges[k - 1].second;
            if (!contiguous) {
                result.uniform = false;
                result.note = ranges.empty()
                                  ? fmt::format("pixel ({}, {}) lies in no part, though inside the merged window {}", x,
                                                y, describeWindow(box))
                                  : fmt::format("the sample ranges of pixel ({}, {}) leave a gap", x, y);
                break;
            }
            const std::pair<uint32_t, uint32_t> span{ranges.front().first, ranges.back().second};
            if (!common) common = span;
            else if (*common != span) {
                result.uniform = false;
                result.note = fmt::format("pixel ({}, {}) holds samples [{}, {}) but pixel ({}, {}) [{}, {})", box.x0,
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
    m.crop = box == PixelWindow{0, result.merged.film.width(), 0, result.merged.film.height()} ? std::nullopt
                                                                                              : std::optional(box);
    return result;
}

MergeResult mergeFilmFiles(const std::vector<std::filesystem::path>& paths) {
    std::vector<FilmFile> parts;
    std::vector<std::string> names;
    for (const auto& path : paths) {
        parts.push_back(readFilmExr(path));
        names.push_back(path.string());
    }
    return mergeFilms(parts, names);
}

void checkResumable(const FilmFile& file, const std::string& path, const ResumeTarget& target) {
    const RenderMetadata& m = file.metadata;
    auto fail = [&](const std::string& message) {
        SourceLocation where;
        where.file = path;
        throw InputError(where, "cannot resume this film: " + message);
    };
    if (m.sceneHash != target.sceneHash)
        fail(fmt::format("it was rendered from a different scene ('{}' hashing to {}; the scene file now hashes to {})",
                         m.sceneFile, m.sceneHash, target.sceneHash));
    if (file.film.width() != target.width || file.film.height() != target.height)
        fail(fmt::format("it is {}x{}, the render {}x{} (pass --res {}x{})", file.film.width(), file.film.height(),
                         target.width, target.height, file.film.width(), file.film.height()));
    if (m.seed != target.seed) fail(fmt::format("it was rendered with seed {}, not {} (pass --seed {})", m.seed, target.seed, m.seed));
    if (m.sampler != target.sampler)
        fail(fmt::format("it was rendered with the {} sampler, not {} (pass --sampler {})", m.sampler, target.sampler, m.sampler));
    if (m.accelerator != target.accelerator)
        fail(fmt::format("it was rendered with --accel {}, not {}", m.accelerator, target.accelerator));
    const PixelWindow full{0, target.width, 0, target.height};
    const PixelWindow fileWindow = m.crop.value_or(full), targetWindow = target.crop.value_or(full);
    if (fileWindow != targetWindow)
        fail(fmt::format("it covers the pixels {}, the render {} (pass --crop {})", describeWindow(fileWindow),
                         describeWindow(targetWindow), describeWindow(fileWindow)));
    auto describeAdaptive = [](const std::optional<AdaptiveSettings>& a) {
        return a ? fmt::format("adaptive sampling {} (THRESHOLD:MIN_SPP)", formatAdaptiveAttribute(*a))
                 : std::string("no adaptive sampling");
    };
    if (m.adaptive != target.adaptive)
        fail(fmt::format("it was rendered with {}, the render asks for {} (pass the same --adaptive and --min-spp)",
                         describeAdaptive(m.adaptive), describeAdaptive(target.adaptive)));
    const uint32_t count = m.endSample - m.firstSample;
    if (m.adaptive) {
        // Each pixel of the window stopped at a decision point or holds every sample.
        if (m.firstSample != 0) fail(fmt::format("an adaptive film starts at sample 0, not {}", m.firstSample));
        for (int y = 0; y < target.height; ++y)
            for (int x = 0; x < target.width; ++x) {
                const uint32_t held = file.film.at(x, y).sampleCount;
                const bool possible = fileWindow.contains(x, y) ? adaptiveCountPossible(*m.adaptive, held, count) : held == 0;
                if (!possible)
                    fail(fmt::format("pixel ({}, {}) holds {} samples, which an adaptive render ({}) of samples {} "
                                     "does not leave",
                                     x, y, held, describeAdaptive(m.adaptive), describeRange(m)));
            }
    }
    for (int y = 0; y < target.height && !m.adaptive; ++y)
        for (int x = 0; x < target.width; ++x) {
            const uint32_t expected = fileWindow.contains(x, y) ? count : 0;
            if (file.film.at(x, y).sampleCount != expected)
                fail(fmt::format("pixel ({}, {}) holds {} samples where its samples {} say {} (a merge of parts that "
                                 "do not cover the same samples everywhere?)",
                                 x, y, file.film.at(x, y).sampleCount, describeRange(m), expected));
        }
    if (m.endSample > target.endSample)
        fail(fmt::format("it already holds samples {}, beyond --spp {}", describeRange(m), target.endSample));
}

}  // namespace penumbra
