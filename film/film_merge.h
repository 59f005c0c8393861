// Merging films and checking that a film can be continued (`penumbra merge`, `render --resume`):
// films rendered from the same scene, resolution, seed, sampler and backend, over sample ranges
// and pixel windows that do not overlap, are added pixel by pixel. The film's sums are exact (ExactSum,
// film/film.h), so a merge gives the same bits as one render of the union, in whatever order the parts come.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "film/film_exr.h"

namespace penumbra {

struct MergeResult {
    FilmFile merged;
    // False when the parts do not give every pixel of the merged window the same contiguous
    // sample range (e.g. a gap between ranges, or crops that leave holes): the per-pixel counts
    // are in the "spp" channel, but such a film cannot be resumed. `note` says why.
    bool uniform = true;
    std::string note;
};

// Merges films one at a time, so that a merge of many parts holds two films in memory, not all
// of them: add() each part (read with readFilmExr; `name`, the file, for messages), then finish().
class FilmMerger {
public:
    // Throws InputError when `part` is not a part of the same render as the first or overlaps
    // an earlier part.
    void add(FilmFile part, const std::string& name);
    // The merged film; throws InputError when nothing was added.
    MergeResult finish();

    // What is kept of each part added: enough to check the next ones and the merged window.
    struct Seen {
        RenderMetadata metadata;
        PixelWindow window;
        std::string name;
    };

private:
    std::optional<FilmFile> merged_;
    Seen first_;
    std::vector<Seen> seen_;
};

// Merges films read with readFilmExr; `names` (the files, for messages) parallel `parts`.
// Throws InputError when they are not parts of one render or overlap, or when one is an adaptive
// render (whose pixels stop where the whole film decides: parts would not add up to one render).
MergeResult mergeFilms(const std::vector<FilmFile>& parts, const std::vector<std::string>& names);

// Reads and merges the files, one at a time (FilmMerger); nothing is written.
MergeResult mergeFilmFiles(const std::vector<std::filesystem::path>& paths);

// What a render that continues `file` must agree on.
struct ResumeTarget {
    std::string sceneHash;
    int width = 0, height = 0;
    uint64_t seed = 0;
    std::string sampler, accelerator;
    std::optional<PixelWindow> crop;
    uint32_t endSample = 0;  // the render is to end at this sample index
    // The render's first sample index (render --samples FIRST:END), when it names one: the film
    // must start there.
    std::optional<uint32_t> firstSample;
    std::optional<AdaptiveSettings> adaptive{};  // the render's adaptive sampling, if any
};

// Throws InputError (naming `path`) unless `file` is a film that a render of `target` can
// continue: same scene contents, resolution, seed, sampler, backend, crop and adaptive sampling,
// every pixel of the window holding the same samples [first, end) (adaptive: [0, k) for a k that
// the adaptive schedule allows, film/adaptive_film.h), end <= target.endSample and, when the
// target names one, first == target.firstSample.
void checkResumable(const FilmFile& file, const std::string& path, const ResumeTarget& target);

// "x0,x1,y0,y1" and "[first, end)", as the command line writes them.
std::string describeWindow(const PixelWindow& window);
std::string describeRange(const RenderMetadata& metadata);

}  // namespace penumbra
