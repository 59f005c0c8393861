// One render of a scene into a film that goes to a file: the sample range it covers (which a
// resumed film starts earlier than this run), the metadata the file records, and the checkpoints
// written between passes. `penumbra render` and `penumbra converge` run their renders as jobs, so
// a film file always says the same things about the render that made it.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>

#include "film/film.h"
#include "film/film_exr.h"
#include "film/scene_hash.h"
#include "renderer/render.h"
#include "scenes/scene.h"

namespace penumbra {

// The scene a film comes from: its file as the user named it and hashSceneFiles() of its contents.
struct SceneSource {
    std::string file;
    std::string hash;
    // Hashes the scene file and the mesh files the loaded scene names.
    static SceneSource of(const std::filesystem::path& sceneFile, const Scene& scene);
};

class RenderJob {
public:
    // Renders samples [options.firstSample, options.endSample) of `scene` (endSample 0: the
    // scene's samples per pixel) into a new film. The scene must outlive the job.
    RenderJob(const Scene& scene, SceneSource source, RenderOptions options);

    // Continues the film in `path` instead of a new one: its samples [first, end) are kept and
    // this run renders [end, options.endSample). With `startingAt` (render --samples FIRST:END)
    // the film must start at that sample (a checkpoint of the same sample range). Throws
    // InputError naming the file when it is not a film of this render (checkResumable,
    // film/film_merge.h).
    void resumeFrom(const std::filesystem::path& path, std::optional<uint32_t> startingAt = std::nullopt);

    // During run(), writes the film to `path` after a pass whenever `minutes` have passed since
    // the last write (0: after every pass), then calls `written` with the film's sample range.
    void checkpointEvery(double minutes, std::filesystem::path path,
                         std::function<void(uint32_t first, uint32_t end)> written = {});

    // Renders, once per job; `afterPass` (if any) is called after each pass, before a checkpoint,
    // with the film holding samples [firstSample(), passEnd) (as RenderOptions::passDone).
    RenderStats run(const std::function<void(uint32_t passEnd)>& afterPass = {});

    // What the film's file records when it holds samples [firstSample(), end), rendered in
    // `seconds` (this run's and any resumed film's).
    RenderMetadata metadataAt(uint32_t end, double seconds) const;
    // The same after run().
    RenderMetadata metadata() const;
    // Writes the film with metadata() (film/film_exr.h: atomic, nothing half-written);
    // checkpoints are always FilmContents::Full.
    void writeFilm(const std::filesystem::path& path, FilmContents contents = FilmContents::Full) const;

    const Film& film() const { return film_; }
    Film& film() { return film_; }
    // The first sample index the film holds (earlier than this run's when resumed).
    uint32_t firstSample() const { return firstSample_; }
    // The first sample index this run renders (the resumed film's end when resumed).
    uint32_t runFirstSample() const { return options_.firstSample; }
    // The sample index the job renders up to.
    uint32_t endSample() const { return options_.endSample; }
    bool resumed() const { return resumed_; }

private:
    const Scene& scene_;
    SceneSource source_;
    RenderOptions options_;
    Film film_;
    uint32_t firstSample_ = 0;
    bool resumed_ = false;
    double previousSeconds_ = 0.0;  // the resumed film's render time
    std::optional<RenderStats> stats_;
    struct Checkpoints {
        double minutes = 0;
        std::filesystem::path path;
        std::function<void(uint32_t, uint32_t)> written;
    };
    std::optional<Checkpoints> checkpoints_;
};

}  // namespace penumbra
