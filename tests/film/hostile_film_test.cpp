// Corrupt and crafted films (tests/data/hostile): what `render --resume` and `merge` read must be
// verified (the checksum of docs/exr-layout.md) and must not overflow the exact sums or wrap the
// sample counts when added. Each case was once accepted silently.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "film/atomic_file.h"
#include "film/checked_file.h"
#include "film/film_exr.h"
#include "film/film_merge.h"
#include "tests/support/expect_input_error.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;
using testing::catchInputError;

const fs::path kHostile = fs::path(PENUMBRA_TEST_DATA_DIR) / "hostile";

// A 4x2 film whose every pixel holds samples [first, end) of weight 1 and radiance 0.5.
FilmFile filmOfSamples(uint32_t first, uint32_t end) {
    FilmFile f{Film(4, 2), {}};
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 4; ++x)
            for (uint32_t s = first; s < end; ++s) f.film.add(x, y, Rgb(0.5f), 1.0f);
    RenderMetadata& m = f.metadata;
    m.seed = 1;
    m.sampler = "stratified";
    m.accelerator = "embree";
    m.sceneHash = "fnv1a64:0000000000000001";
    m.firstSample = first;
    m.endSample = end;
    m.samplesPerPixel = int(end - first);
    return f;
}

class HostileFilm : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() /
               ("penumbra-hostile-film-" +
                std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }
    fs::path dir_;
};

// flipped_sums.exr: a 16x12 render with 16 bytes flipped in its RLE part "sums.noise"; OpenEXR
// decodes it without complaint, into wrong sums.
TEST_F(HostileFilm, FlippedBytesInTheRleSumsAreRefused) {
    const fs::path file = kHostile / "flipped_sums.exr";
    const InputError e = catchInputError([&] { readFilmExr(file); });
    EXPECT_EQ(e.where().file, file.string());
    EXPECT_CONTAINS(e.what(), "flipped_sums.exr: the film's sums or metadata do not match their checksum");
    EXPECT_CONTAINS(e.what(), "the file is corrupt");
}

TEST_F(HostileFilm, IntactFilmsCarryAChecksumThatVerifies) {
    const FilmFile f = filmOfSamples(0, 3);
    writeExr(f.film, f.metadata, dir_ / "good.exr");
    EXPECT_TRUE(readFilmExr(dir_ / "good.exr").film.identicalTo(f.film));
}

TEST_F(HostileFilm, SumsBeyondWhat2To32SamplesCanAddAreRefused) {
    FilmFile f = filmOfSamples(0, 1);
    const uint32_t words[4] = {0, 0, 0, 0x40000000u};  // 2^126 units
    PixelSums pixel = f.film.at(2, 1);
    pixel.weight = ExactSum::fromWords(words);
    f.film.set(2, 1, pixel);
    writeExr(f.film, f.metadata, dir_ / "huge.exr");  // its checksum is right: only the range tells
    const InputError e = catchInputError([&] { readFilmExr(dir_ / "huge.exr"); });
    EXPECT_CONTAINS(e.what(), "huge.exr: pixel (2, 1): sum.weight is beyond what 2^32 samples can add");
}

TEST_F(HostileFilm, MergeRefusesSampleCountsThatWouldPass2To32) {
    FilmFile a = filmOfSamples(0, 1), b = filmOfSamples(1, 2);
    PixelSums crafted = a.film.at(3, 0);
    crafted.sampleCount = 0xfffffff0u;  // crafted: the count disagrees with the metadata
    a.film.set(3, 0, crafted);
    crafted.sampleCount = 0x20u;
    b.film.set(3, 0, crafted);
    const InputError e = catchInputError([&] { mergeFilms({a, b}, {"a.exr", "b.exr"}); });
    EXPECT_CONTAINS(e.what(), "cannot merge b.exr: pixel (3, 0) would hold more than 2^32 - 1 samples");
}

TEST_F(HostileFilm, MergeRefusesSumsThatWouldOverflow128Bits) {
    FilmFile a = filmOfSamples(0, 1), b = filmOfSamples(1, 2);
    const uint32_t words[4] = {0, 0, 0, 0x7fffffffu};
    for (Film* film : {&a.film, &b.film}) {
        PixelSums pixel = film->at(0, 1);
        pixel.radiance[1] = ExactSum::fromWords(words);
        film->set(0, 1, pixel);
    }
    const InputError e = catchInputError([&] { mergeFilms({a, b}, {"a.exr", "b.exr"}); });
    EXPECT_CONTAINS(e.what(), "cannot merge b.exr: pixel (0, 1) would hold");
}

// declared_9000x9000.exr (made by make_declared_9000.py): headers that declare 9000x9000 pixels
// in 151 KB, none of whose rows are there. It once allocated a 19.3 GiB film before any check.
TEST_F(HostileFilm, DeclaredSizeIsCheckedAgainstTheFileBeforeAllocating) {
    const InputError e = catchInputError([] { readFilmExr(kHostile / "declared_9000x9000.exr"); });
    EXPECT_CONTAINS(e.what(),
                    "declared_9000x9000.exr: the file is 151752 bytes, too small for the rows its windows "
                    "declare (at least 371260 bytes)");
}

// OpenEXR 3.1's C++ reader allocates (and clears) what a header attribute declares before reading
// it, and reads a channel list by its contents whatever size it declares, then goes on from there.
// Found by fuzz/film_fuzzer: attribute_declares_1_8_gib.exr (4 KB; an attribute of 1866474240
// bytes) and channel_list_beyond_its_size.exr (a channel list that runs into the next attribute,
// which then declares 1.8 GB); unknown_attribute_1_8_gib.exr is a film whose "penumbra:scene"
// has an unknown type and 1.8 GB. Each took 1.8 GB and seconds to refuse; now OpenEXR's C core
// parses the headers first, checking each size against the file, and nothing large is allocated.
// isPenumbraFilm, which opens the header too, says no the same way.
TEST_F(HostileFilm, HeadersAreCheckedBeforeOpenExrAllocatesWhatTheyDeclare) {
    const std::pair<const char*, const char*> cases[] = {
        {"attribute_declares_1_8_gib.exr", "Invalid empty string encountered parsing attribute type"},
        {"channel_list_beyond_its_size.exr", "Invalid pixel type specified"},
        {"unknown_attribute_1_8_gib.exr",
         "Attribute 'penumbra:scene', type 'strinX': Invalid size 1879048192"}};
    for (const auto& [name, reason] : cases) {
        const fs::path file = kHostile / name;
        const InputError e = catchInputError([&] { readFilmExr(file); });
        EXPECT_CONTAINS(e.what(), std::string(name) + ": cannot read the image: ");
        EXPECT_CONTAINS(e.what(), reason);
        EXPECT_FALSE(isPenumbraFilm(file)) << name;
    }
}

// /dev/full fails every write with ENOSPC, as a full disk does. A write larger than the buffer
// goes to the system at once and fails there; a small one is buffered and fails at close().
TEST(CheckedFile, AFailedWriteIsAnErrorNamingTheFile) {
    {
        CheckedFile file("/dev/full");
        file.write("x", 1);
        try {
            file.close();
            ADD_FAILURE() << "close() after a buffered write to /dev/full succeeded";
        } catch (const std::runtime_error& e) {
            EXPECT_CONTAINS(e.what(), "write of '/dev/full' failed: No space left on device");
        }
    }
    CheckedFile file("/dev/full");
    const std::vector<char> large(CheckedFile::kBufferSize + 1, 'x');
    try {
        file.write(large.data(), large.size());
        ADD_FAILURE() << "a write to /dev/full succeeded";
    } catch (const std::runtime_error& e) {
        EXPECT_CONTAINS(e.what(), "write of '/dev/full' failed: No space left on device");
    }
    // A caller that swallowed the failure (OpenEXR's destructors do) still learns of it at close().
    try {
        file.close();
        ADD_FAILURE() << "close() after a failed write succeeded";
    } catch (const std::runtime_error& e) {
        EXPECT_CONTAINS(e.what(), "write of '/dev/full' failed: No space left on device");
    }
}

// A process number that belonged to a process that has ended.
long deadProcessId() {
    const pid_t child = fork();
    if (child == 0) _exit(0);
    waitpid(child, nullptr, 0);
    return long(child);
}

// A writer killed with SIGKILL leaves its folder NAME.exr.tmp-PID-XXXXXX; the next write to
// NAME.exr removes it once its process is gone (and it has not been touched for a minute), and
// keeps the others.
TEST_F(HostileFilm, StaleTemporariesOfDeadWritersAreRemoved) {
    const fs::path destination = dir_ / "image.exr";
    const fs::path stale = dir_ / ("image.exr.tmp-" + std::to_string(deadProcessId()) + "-Ab12Cd");
    const fs::path recent = dir_ / ("image.exr.tmp-" + std::to_string(deadProcessId()) + "-Ef34Gh");
    const fs::path alive = dir_ / ("image.exr.tmp-" + std::to_string(long(getppid())) + "-Ij56Kl");
    const fs::path otherDestination = dir_ / ("image.png.tmp-" + std::to_string(deadProcessId()) + "-Mn78Op");
    for (const fs::path& p : {stale, recent, alive, otherDestination}) {
        fs::create_directory(p);
        std::ofstream(p / p.filename().string().substr(0, 9)) << "half-written";
    }
    const auto old = fs::file_time_type::clock::now() - std::chrono::minutes(5);
    for (const fs::path& p : {stale, alive, otherDestination}) fs::last_write_time(p, old);

    writeFileAtomically(destination, "test file", [](const std::string& tmp, std::string&) {
        std::ofstream(tmp) << "complete";
        return true;
    });
    EXPECT_TRUE(fs::exists(destination));
    EXPECT_FALSE(fs::exists(stale)) << "the temporary of a dead writer was left";
    EXPECT_TRUE(fs::exists(recent)) << "a temporary modified within the minute was removed";
    EXPECT_TRUE(fs::exists(alive)) << "the temporary of a live process was removed";
    EXPECT_TRUE(fs::exists(otherDestination)) << "another destination's temporary was removed";
}

// A link planted in a shared folder where a writer's temporary goes (once NAME.tmp-PID.EXT, a
// name anyone could predict) must not redirect the write: the temporary is a file in a folder of
// the writer's own, made with a name nobody knew in advance, and nothing else is touched.
TEST_F(HostileFilm, ALinkPlantedWhereTheTemporaryGoesIsNotFollowed) {
    const fs::path destination = dir_ / "image.exr";
    const fs::path victim = dir_ / "victim.txt";
    std::ofstream(victim) << "someone else's file";
    const fs::path planted = dir_ / ("image.tmp-" + std::to_string(long(getpid())) + ".exr");
    fs::create_symlink(victim, planted);
    std::string writtenTo;
    writeFileAtomically(destination, "test file", [&](const std::string& tmp, std::string&) {
        writtenTo = tmp;
        std::ofstream(tmp) << "complete";
        return true;
    });
    std::ifstream in(victim);
    EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), "someone else's file");
    std::ifstream out(destination);
    EXPECT_EQ(std::string(std::istreambuf_iterator<char>(out), {}), "complete");
    EXPECT_FALSE(fs::is_symlink(destination));
    // Written in a private folder, which is gone: only the destination, the victim and the link remain.
    EXPECT_EQ(fs::path(writtenTo).filename(), "image.exr");
    EXPECT_NE(fs::path(writtenTo).parent_path(), dir_);
    EXPECT_FALSE(fs::exists(fs::path(writtenTo).parent_path()));
    size_t entries = 0;
    for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir_)) ++entries;
    EXPECT_EQ(entries, 3u);
}

}  // namespace
}  // namespace penumbra
