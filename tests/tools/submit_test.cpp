// `penumbra submit`, `merge --manifest` and `status` without a cluster: the batch scripts of a
// dry run, the checks made before anything is submitted, and a manifest whose parts are missing
// or partial refused by name and range (the cluster itself: slurm_test.cpp).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "core/error.h"
#include "film/film_exr.h"
#include "film/scene_hash.h"
#include "tests/support/run_command.h"
#include "tools/part_manifest.h"
#include "tools/run_program.h"
#include "tools/slurm_batch.h"

namespace fs = std::filesystem;

namespace penumbra {
namespace {

using testing::runPenumbra;
using testing::RunResult;
using testing::runShell;

const std::string kScene = std::string(PENUMBRA_SOURCE_DIR) + "/scenes/soft-shadows.json";

bool contains(const RunResult& r, const std::string& what) {
    return r.output.find(what) != std::string::npos;
}

class SplitRender : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() / ("penumbra-split-" + std::to_string(::getpid()) + "-" +
                                            ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }
    std::string path(const std::string& name) const { return (dir_ / name).string(); }
    size_t fileCount() const {
        size_t n = 0;
        for (auto it = fs::recursive_directory_iterator(dir_); it != fs::recursive_directory_iterator(); ++it)
            ++n;
        return n;
    }
    // A manifest of two sample-range parts of a 32x24 render at 4 spp, as submit writes it.
    PartManifest twoParts() {
        PartManifest m;
        m.scene = kScene;
        m.output = path("out.exr");
        m.penumbra = PENUMBRA_BINARY;
        m.sceneHash = hashSceneFiles(kScene, {});
        m.seed = 0;
        m.sampler = "stratified";
        m.accelerator = "embree";
        m.width = 32;
        m.height = 24;
        m.samplesPerPixel = 4;
        m.renderArguments = {"--res", "32x24"};
        m.parts = splitRender(SplitKind::Samples, 2, 4, 32, 24, partsFolderFor(m.output));
        writeManifest(m, path("out.parts.json"));
        fs::create_directories(path("out.parts"));
        return m;
    }
    void renderPart(const std::string& samples, const std::string& extra = "") {
        const RunResult r = runPenumbra(
            "render " + kScene + " --res 32x24 --spp 4 -q --no-display --samples " + samples + " " + extra);
        ASSERT_EQ(r.exitCode, 0) << r.output;
    }

    fs::path dir_;
};

TEST_F(SplitRender, SplitsAreEvenContiguousAndComplete) {
    const auto parts = splitRender(SplitKind::Samples, 3, 10, 8, 8, "p");
    ASSERT_EQ(parts.size(), 3u);
    EXPECT_EQ(parts[0].firstSample, 0u);
    EXPECT_EQ(parts[0].endSample, 3u);
    EXPECT_EQ(parts[1].firstSample, 3u);
    EXPECT_EQ(parts[2].endSample, 10u);
    const auto rows = splitRender(SplitKind::Rows, 4, 16, 10, 9, "p");
    ASSERT_EQ(rows.size(), 4u);
    EXPECT_EQ(rows[0].crop->y0, 0);
    EXPECT_EQ(rows[3].crop->y1, 9);
    for (size_t i = 1; i < rows.size(); ++i) EXPECT_EQ(rows[i].crop->y0, rows[i - 1].crop->y1);
    EXPECT_EQ(rows[2].endSample, 16u);
    EXPECT_THROW(splitRender(SplitKind::Samples, 11, 10, 8, 8, "p"), InputError);
    // A tree above the threshold: groups of ceil(sqrt(N)) consecutive parts that cover them all.
    EXPECT_TRUE(mergeGroups(16, 16, "p").empty());
    const auto groups = mergeGroups(1000, 16, "p");
    ASSERT_EQ(groups.size(), 32u);
    EXPECT_EQ(groups[0].endPart, 32);
    EXPECT_EQ(groups.back().endPart, 1000);
}
bool contains(const ProgramResult& r, const std::string& what) {
    return r.output.find(what) != std::string::npos;
}

// `penumbra` with exactly these arguments, no shell between.
ProgramResult runPenumbraWith(std::vector<std::string> arguments) {
    arguments.insert(arguments.begin(), PENUMBRA_BINARY);
    return runProgram(arguments);
}

std::string readText(const fs::path& path) {
    std::ifstream in(path);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// A name a shell would act on in every way it can: spaces, both quotes, $(...), backticks, a
// glob, a comment, and Slurm's own '%' patterns.
const std::string kHostileName = "a b'c\"d$(touch INJECTED)e`touch INJECTED`f*g#h%j%a";

TEST_F(SplitRender, DryRunPrintsTheBatchScriptsAndWritesNothing) {
    const RunResult r =
        runPenumbra("submit " + kScene + " --parts 4 --spp 16 --res 32x24 -o " + path("out.exr") +
                    " --dry-run --partition gpu --time 1:00:00 --sbatch=--account=lab --seed 7");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_TRUE(contains(r, "#SBATCH --array=0-3")) << r.output;
    EXPECT_TRUE(contains(r, "#SBATCH --partition=gpu"));
    EXPECT_TRUE(contains(r, "#SBATCH --time=1:00:00"));
    EXPECT_TRUE(contains(r, "#SBATCH --signal=B:TERM@120"));
    EXPECT_TRUE(contains(r, "#SBATCH --account=lab"));
    EXPECT_TRUE(contains(r, "#SBATCH --requeue"));
    EXPECT_TRUE(contains(r, "3) part='" + path("out.parts/part-0003.exr") + "'; range=(--samples 12:16)"));
    EXPECT_TRUE(contains(r, "'--seed' '7'"));
    EXPECT_TRUE(contains(r, "merge --manifest '" + path("out.parts.json") + "'"));
    EXPECT_TRUE(contains(r, "nothing written or submitted"));
    EXPECT_EQ(fileCount(), 0u);
}

TEST_F(SplitRender, BadInputIsRefusedBeforeAnythingIsSubmitted) {
    const std::string common = " --parts 4 --spp 16 --res 32x24 -o ";
    const RunResult noScene = runPenumbra("submit " + path("missing.json") + common + path("out.exr"));
    EXPECT_EQ(noScene.exitCode, 1);
    EXPECT_TRUE(contains(noScene, "missing.json")) << noScene.output;
    const RunResult notExr = runPenumbra("submit " + kScene + common + path("out.png"));
    EXPECT_TRUE(contains(notExr, "expected a path ending in .exr")) << notExr.output;
    // A folder that does not exist yet is made by the submit; a dry run writes nothing there.
    const RunResult noFolder =
        runPenumbra("submit " + kScene + common + path("nowhere/out.exr") + " --dry-run");
    EXPECT_EQ(noFolder.exitCode, 0) << noFolder.output;
    EXPECT_TRUE(contains(noFolder, path("nowhere/out.parts/render.sbatch"))) << noFolder.output;
    const RunResult tooMany = runPenumbra("submit " + kScene + " --parts 17 --spp 16 -o " + path("out.exr"));
    EXPECT_TRUE(contains(tooMany, "17 parts of 16 samples per pixel")) << tooMany.output;
    const RunResult noSbatch = runShell("PATH=/nonexistent " + std::string(PENUMBRA_BINARY) + " submit " +
                                        kScene + common + path("out.exr"));
    EXPECT_EQ(noSbatch.exitCode, 1);
    EXPECT_TRUE(contains(noSbatch, "sbatch is not on PATH")) << noSbatch.output;
    const RunResult noManifest = runPenumbra("submit " + kScene + common + path("out.exr") + " --resume");
    EXPECT_TRUE(contains(noManifest, "there is no manifest")) << noManifest.output;
    EXPECT_EQ(fileCount(), 0u);

    twoParts();
    const RunResult again = runPenumbra("submit " + kScene + common + path("out.exr"));
    EXPECT_TRUE(contains(again, "this output was submitted before; pass --resume")) << again.output;
    const RunResult otherSpp = runPenumbra("submit " + kScene + " --parts 2 --spp 8 --res 32x24 -o " +
                                           path("out.exr") + " --resume --dry-run");
    EXPECT_TRUE(contains(otherSpp, "this submit has --spp 8, the manifest 4")) << otherSpp.output;
}

TEST_F(SplitRender, MergeOfAManifestNamesMissingAndPartialPartsAndWritesNothing) {
    const PartManifest m = twoParts();
    renderPart("0:2", "-o " + m.parts[0].file.string());

    const RunResult missing = runPenumbra("merge --manifest " + path("out.parts.json"));
    EXPECT_EQ(missing.exitCode, 1);
    EXPECT_TRUE(contains(missing, path("out.parts.json") + ": 1 of 2 parts are not done; nothing merged"))
        << missing.output;
    EXPECT_TRUE(contains(missing, "part 1 (samples [2, 4), " + m.parts[1].file.string() + "): missing"))
        << missing.output;
    EXPECT_FALSE(fs::exists(path("out.exr")));

    // A checkpoint of part 1 that holds only its first sample: partial, still refused.
    renderPart("2:3", "-o " + m.parts[1].file.string());
    const RunResult partial = runPenumbra("merge --manifest " + path("out.parts.json"));
    EXPECT_EQ(partial.exitCode, 1);
    EXPECT_TRUE(contains(partial, "part 1 (samples [2, 4)")) << partial.output;
    EXPECT_TRUE(contains(partial, "partial: a checkpoint holds samples [2, 3) of [2, 4)")) << partial.output;
    EXPECT_FALSE(fs::exists(path("out.exr")));
    const RunResult status = runPenumbra("status " + path("out.exr"));
    EXPECT_EQ(status.exitCode, 0);
    EXPECT_TRUE(contains(status, "2 parts: 1 done, 1 partial, 0 started, 0 missing; 75.0% of the samples"))
        << status.output;

    // A part from another render is named as such.
    renderPart("0:2", "--seed 9 -o " + path("other.exr"));
    fs::copy_file(m.parts[0].file, path("part0.exr"));
    fs::copy_file(path("other.exr"), m.parts[0].file, fs::copy_options::overwrite_existing);

    // Part 1 continues its own checkpoint; then the merge is one render's film, bit for bit.
    renderPart("2:4", "--resume " + m.parts[1].file.string() + " -o " + m.parts[1].file.string());
    const RunResult foreign = runPenumbra("merge --manifest " + path("out.parts.json"));
    EXPECT_EQ(foreign.exitCode, 1);
    EXPECT_TRUE(contains(foreign, "part 0 (samples [0, 2), " + m.parts[0].file.string() +
                                      "): not this part's film: it was rendered with seed 9"))
        << foreign.output;
    EXPECT_FALSE(fs::exists(path("out.exr")));
    fs::copy_file(path("part0.exr"), m.parts[0].file, fs::copy_options::overwrite_existing);
    const RunResult merged = runPenumbra("merge --manifest " + path("out.parts.json") + " --no-display");
    ASSERT_EQ(merged.exitCode, 0) << merged.output;
    renderPart("0:4", "-o " + path("once.exr"));
    EXPECT_TRUE(readFilmExr(path("out.exr")).film.identicalTo(readFilmExr(path("once.exr")).film));
}

TEST_F(SplitRender, ABadManifestIsReportedAtItsJsonPointer) {
    twoParts();
    std::ifstream in(path("out.parts.json"));
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const size_t at = text.find("\"samples\": [\n        2,\n        4\n      ]");
    ASSERT_NE(at, std::string::npos) << text;
    text.replace(at, 0, "\"sample\": 1, ");
    std::ofstream(path("out.parts.json")) << text;
    const RunResult r = runPenumbra("merge --manifest " + path("out.parts.json"));
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_TRUE(contains(r, path("out.parts.json") + ": /parts/1/sample")) << r.output;
}

// Every value a batch script holds is one line: a newline, carriage return or other control
// character in the output's name, --partition, --time or --sbatch is refused before anything is
// written (in a script it would be a command of its own, run on the compute node).
TEST_F(SplitRender, ControlCharactersInAnyScriptValueAreRefusedBeforeAnythingIsWritten) {
    const std::string injected = "\ntouch INJECTED\n#";
    const std::vector<std::vector<std::string>> attempts = {
        {"-o", path("x" + injected + ".exr")},
        {"-o", path("out.exr"), "--partition", "batch" + injected},
        {"-o", path("out.exr"), "--time", "1:00" + injected},
        {"-o", path("out.exr"), "--sbatch", "--account=lab" + injected},
        {"-o", path("out.exr"), "--sbatch", std::string("--comment=a\rb")},
    };
    for (const auto& extra : attempts) {
        std::vector<std::string> arguments = {"submit", kScene, "--parts", "2",
                                              "--spp",  "4",    "--res",   "16x12"};
        arguments.insert(arguments.end(), extra.begin(), extra.end());
        // With sbatch on PATH or not, the refusal comes first; without it nothing could be submitted anyway.
        const ProgramResult r = runPenumbraWith(arguments);
        EXPECT_EQ(r.exitStatus, 1) << r.output;
        EXPECT_TRUE(contains(r, "contains a control character")) << r.output;
        arguments.push_back("--dry-run");
        const ProgramResult dry = runPenumbraWith(arguments);
        EXPECT_EQ(dry.exitStatus, 1) << dry.output;
        EXPECT_FALSE(contains(dry, "#SBATCH")) << dry.output;
    }
    EXPECT_EQ(fileCount(), 0u);
    const ProgramResult nan =
        runPenumbraWith({"submit", kScene, "--parts", "2", "-o", path("out.exr"), "--checkpoint", "nan"});
    EXPECT_EQ(nan.exitStatus, 2) << nan.output;
    EXPECT_TRUE(contains(nan, "expected a finite number of minutes")) << nan.output;
    const ProgramResult inf =
        runPenumbraWith({"render", kScene, "-o", path("out.exr"), "--checkpoint", "inf"});
    EXPECT_EQ(inf.exitStatus, 2) << inf.output;
    EXPECT_EQ(fileCount(), 0u);
}

// The render script run as Slurm runs an array task (bash, SLURM_ARRAY_TASK_ID set), in a folder
// whose name holds everything a shell acts on: the part is rendered to its file under that name
// and nothing in the name runs.
TEST_F(SplitRender, ARenderScriptRunsWithAHostileFolderNameAsItIs) {
    const fs::path folder = dir_ / kHostileName;
    fs::create_directories(folder);
    PartManifest m;
    m.scene = kScene;
    m.output = folder / "out.exr";
    m.penumbra = PENUMBRA_BINARY;
    m.samplesPerPixel = 2;
    m.width = 16;
    m.height = 12;
    m.renderArguments = {"--res", "16x12", "--seed", "3"};
    m.parts = splitRender(SplitKind::Samples, 2, 2, 16, 12, partsFolderFor(m.output));
    SlurmRequest request;
    request.sbatchArguments = {"--comment=" + kHostileName};
    const std::string script = renderScript(m, manifestPathFor(m.output), request, {0, 1});
    fs::create_directories(partsFolderFor(m.output));
    std::ofstream(path("render.sbatch")) << script;

    const ProgramResult task =
        runProgram({"env", "SLURM_ARRAY_TASK_ID=1", "SLURM_JOB_ID=7", "bash", path("render.sbatch")});
    EXPECT_EQ(task.exitStatus, 0) << task.output << "\n" << script;
    EXPECT_TRUE(fs::exists(m.parts[1].file)) << script;
    EXPECT_FALSE(fs::exists(m.parts[0].file));
    for (auto it = fs::recursive_directory_iterator(dir_); it != fs::recursive_directory_iterator(); ++it)
        EXPECT_NE(it->path().filename(), "INJECTED") << it->path();
    EXPECT_FALSE(fs::exists(fs::current_path() / "INJECTED"));
    // In "...", \" is a quote and '#' is not a comment; '%' is doubled where Slurm reads a file
    // name pattern (--output).
    const std::string quotedName = R"(a b'c\"d$(touch INJECTED)e`touch INJECTED`f*g#h)";
    EXPECT_NE(script.find("#SBATCH --output=\"" + dir_.string() + "/" + quotedName +
                          "%%j%%a/out.parts/logs/part-%4a.log\"\n"),
              std::string::npos)
        << script;
    EXPECT_NE(script.find("#SBATCH \"--comment=" + quotedName + "%j%a\"\n"), std::string::npos) << script;
}

// A manifest names its output, parts and merge groups only as submit names them beside it: a
// crafted one cannot make `merge --manifest` overwrite another file (a text file, a picture, a
// finished part's film), and an existing file that is not a penumbra film is never overwritten.
TEST_F(SplitRender, ACraftedManifestCannotChooseWhatMergeOverwrites) {
    const PartManifest m = twoParts();
    renderPart("0:2", "-o " + m.parts[0].file.string());
    renderPart("2:4", "-o " + m.parts[1].file.string());
    std::ofstream(path("notes.txt")) << "someone's notes";
    const std::string manifestText = readText(path("out.parts.json"));
    auto craft = [&](const std::string& from, const std::string& to) {
        std::string text = manifestText;
        const size_t at = text.find(from);
        EXPECT_NE(at, std::string::npos) << from;
        if (at != std::string::npos) text.replace(at, from.size(), to);
        std::ofstream(path("out.parts.json")) << text;
    };
    const std::string partBefore = readText(m.parts[0].file);

    craft("\"output\": \"" + path("out.exr") + "\"", "\"output\": \"" + path("notes.txt") + "\"");
    ProgramResult r = runPenumbraWith({"merge", "--manifest", path("out.parts.json")});
    EXPECT_EQ(r.exitStatus, 1) << r.output;
    EXPECT_TRUE(contains(r, path("out.parts.json") + ": /output: expected " + path("out.exr"))) << r.output;

    craft("\"output\": \"" + path("out.exr") + "\"", "\"output\": \"" + m.parts[0].file.string() + "\"");
    r = runPenumbraWith({"merge", "--manifest", path("out.parts.json")});
    EXPECT_EQ(r.exitStatus, 1) << r.output;
    EXPECT_TRUE(contains(r, "/output: expected")) << r.output;

    craft("\"file\": \"" + m.parts[1].file.string() + "\"", "\"file\": \"" + path("notes.txt") + "\"");
    r = runPenumbraWith({"merge", "--manifest", path("out.parts.json")});
    EXPECT_EQ(r.exitStatus, 1) << r.output;
    EXPECT_TRUE(contains(r, "/parts/1/file: expected " + m.parts[1].file.string())) << r.output;

    // The manifest as submit wrote it, but a file that is not a film where the output goes: kept.
    std::ofstream(path("out.parts.json")) << manifestText;
    std::ofstream(path("out.exr")) << "not a film";
    r = runPenumbraWith({"merge", "--manifest", path("out.parts.json"), "--no-display"});
    EXPECT_EQ(r.exitStatus, 1) << r.output;
    EXPECT_TRUE(contains(r, path("out.exr") + " exists and is not a penumbra film")) << r.output;
    EXPECT_EQ(readText(path("out.exr")), "not a film");
    // -o may not name one of the films being merged.
    r = runPenumbraWith({"merge", "--manifest", path("out.parts.json"), "-o", m.parts[1].file.string()});
    EXPECT_EQ(r.exitStatus, 1) << r.output;
    EXPECT_TRUE(contains(r, "is one of the films being merged")) << r.output;
    r = runPenumbraWith(
        {"merge", m.parts[0].file.string(), m.parts[1].file.string(), "-o", m.parts[0].file.string()});
    EXPECT_EQ(r.exitStatus, 1) << r.output;
    EXPECT_TRUE(contains(r, "is one of the films being merged")) << r.output;

    EXPECT_EQ(readText(path("notes.txt")), "someone's notes");
    EXPECT_EQ(readText(m.parts[0].file), partBefore);
    // Once the file is moved away, the same manifest merges.
    fs::remove(path("out.exr"));
    r = runPenumbraWith({"merge", "--manifest", path("out.parts.json"), "--no-display"});
    EXPECT_EQ(r.exitStatus, 0) << r.output;
}

}  // namespace
}  // namespace penumbra
