// The film reader used by `render --resume` and `merge` (readFilmExr: OpenEXR, our layout and
// checksum checks), then what those commands do with a film that reads: the resume checks against
// the film's own metadata and a merge of the film with itself (refused: the parts overlap) and
// alone.
#include "film/film_exr.h"
#include "film/film_merge.h"
#include "fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace penumbra;
    static fuzz::ScratchFile exr("fuzz.exr");
    return fuzz::expectReadOrInputError([&] {
        const std::filesystem::path& path = exr.write(data, size);
        const FilmFile film = readFilmExr(path);
        const RenderMetadata& m = film.metadata;
        ResumeTarget target{m.sceneHash, film.film.width(), film.film.height(),
                            m.seed,      m.sampler,         m.accelerator,
                            m.crop,      m.endSample};
        fuzz::expectReadOrInputError([&] { checkResumable(film, path.string(), target); });
        fuzz::expectReadOrInputError([&] { mergeFilms({film, film}, {path.string(), path.string()}); });
        mergeFilms({film}, {path.string()});
    });
}
