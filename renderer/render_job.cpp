#include "renderer/render_job.h"

#include <fmt/format.h>

#include <chrono>
#include <utility>

#include "core/check.h"
#include "core/error.h"
#include "film/film_merge.h"
#include "film/version.h"

namespace penumbra {

SceneSource SceneSource::of(const std::filesystem::path& sceneFile, const Scene& scene) {
    std::vector<std::filesystem::path> files = scene.includedFiles;
    files.insert(files.end(), scene.meshFiles.begin(), scene.meshFiles.end());
    return SceneSource{sceneFile.string(), hashSceneFiles(sceneFile, files)};
}

RenderJob::RenderJob(const Scene& scene, SceneSource source, RenderOptions options)
    : scene_(scene),
      source_(std::move(source)),
      options_(std::move(options)),
      film_(scene.film.width, scene.film.height) {
    if (options_.endSample == 0) options_.endSample = uint32_t(scene.film.samplesPerPixel);
    // Adaptive decisions weigh all of a pixel's samples: a render of a later range alone would
    // decide from part of them.
    if (scene.film.adaptive && options_.firstSample != 0)
        throw InputError(
            fmt::format("adaptive sampling renders from sample 0 (its pixels stop where all their samples "
                        "say so); it cannot render samples from {} alone (--samples)",
                        options_.firstSample));
    firstSample_ = options_.firstSample;
}

void RenderJob::resumeFrom(const std::filesystem::path& path, std::optional<uint32_t> startingAt) {
    FilmFile loaded = readFilmExr(path);
    checkResumable(loaded, path.string(),
                   ResumeTarget{source_.hash, scene_.film.width, scene_.film.height, scene_.settings.seed,
                                std::string(samplerKindName(scene_.settings.sampler)),
                                std::string(acceleratorKindName(options_.accelerator)), options_.crop,
                                options_.endSample, startingAt, scene_.film.adaptive});
    firstSample_ = loaded.metadata.firstSample;
    options_.firstSample = loaded.metadata.endSample;
    previousSeconds_ = loaded.metadata.renderSeconds;
    film_ = std::move(loaded.film);
    resumed_ = true;
}

void RenderJob::checkpointEvery(double minutes, std::filesystem::path path,
                                std::function<void(uint32_t, uint32_t)> written) {
    if (!(minutes >= 0)) throw InputError("--checkpoint: expected a number of minutes >= 0");
    checkpoints_ = Checkpoints{minutes, std::move(path), std::move(written)};
}

RenderStats RenderJob::run(const std::function<void(uint32_t)>& afterPass) {
    PENUMBRA_CHECK(!stats_, "a job runs once");
    using Clock = std::chrono::steady_clock;
    const auto start = Clock::now();
    auto lastCheckpoint = start;
    RenderOptions options = options_;
    options.passDone = [&](uint32_t passEnd) {
        if (options_.passDone) options_.passDone(passEnd);
        if (afterPass) afterPass(passEnd);
        if (!checkpoints_ || passEnd >= options_.endSample) return;
        const auto now = Clock::now();
        if (std::chrono::duration<double>(now - lastCheckpoint).count() < checkpoints_->minutes * 60.0)
            return;
        writeExr(film_,
                 metadataAt(passEnd, previousSeconds_ + std::chrono::duration<double>(now - start).count()),
                 checkpoints_->path);
        lastCheckpoint = Clock::now();
        if (checkpoints_->written) checkpoints_->written(firstSample_, passEnd);
    };
    stats_ = render(scene_, options, film_);
    return *stats_;
}

RenderMetadata RenderJob::metadataAt(uint32_t end, double seconds) const {
    RenderMetadata m;
    m.samplesPerPixel = int(end - firstSample_);
    m.seed = scene_.settings.seed;
    m.sampler = samplerKindName(scene_.settings.sampler);
    m.accelerator = acceleratorKindName(options_.accelerator);
    m.sceneFile = source_.file;
    m.sceneHash = source_.hash;
    m.renderSeconds = seconds;
    m.version = penumbraVersion();
    m.firstSample = firstSample_;
    m.endSample = end;
    m.crop = options_.crop;
    m.adaptive = scene_.film.adaptive;
    return m;
}

RenderMetadata RenderJob::metadata() const {
    PENUMBRA_CHECK(stats_, "metadata() is the finished run's");
    return metadataAt(stats_->endSample, previousSeconds_ + stats_->renderSeconds);
}

void RenderJob::writeFilm(const std::filesystem::path& path, FilmContents contents) const {
    writeExr(film_, metadata(), path, contents);
}

}  // namespace penumbra
