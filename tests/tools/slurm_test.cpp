// `penumbra submit` on a real single-node Slurm cluster started by the test on this machine
// (tests/support/slurm_cluster.sh: munged, slurmctld and slurmd from Debian's munge and
// slurm-wlm, a minimal slurm.conf in a temporary folder, free localhost ports, everything stopped
// and removed afterwards, and by a watchdog if the test dies). An 8-part job array and its merge
// job give the film of one `penumbra render` bit for bit; so do arrays with a task killed
// mid-render, requeued by Slurm or resubmitted with --resume, which continue the part's own
// checkpoint. The tests skip, saying why, only where the daemons cannot start.
#include <gtest/gtest.h>
#include <stdlib.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

#include "core/error.h"
#include "film/film_exr.h"
#include "tests/support/run_command.h"
#include "tools/run_program.h"

namespace fs = std::filesystem;

namespace penumbra {
namespace {

using testing::runPenumbra;
using testing::RunResult;
using testing::runShell;
using Clock = std::chrono::steady_clock;

const std::string kClusterScript = std::string(PENUMBRA_SOURCE_DIR) + "/tests/support/slurm_cluster.sh";
const std::string kScene = std::string(PENUMBRA_SOURCE_DIR) + "/scenes/soft-shadows.json";

bool contains(const std::string& text, const std::string& what) {
    return text.find(what) != std::string::npos;
}

std::string readText(const fs::path& path) {
    std::ifstream in(path);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

class SlurmCluster : public ::testing::Test {
protected:
    void SetUp() override {
        char pattern[] = "/tmp/penumbra-slurm-XXXXXX";  // short: slurmstepd's socket paths are limited
        ASSERT_NE(::mkdtemp(pattern), nullptr);
        dir_ = pattern;
        const RunResult r = runShell(kClusterScript + " start " + (dir_ / "cluster").string() + " " +
                                     std::to_string(::getpid()));
        if (r.exitCode == 2 || r.exitCode == 3)
            GTEST_SKIP()
                << "no Slurm cluster can run on this machine, so penumbra submit is not tested here:\n"
                << r.output;
        ASSERT_EQ(r.exitCode, 0) << r.output;
        ::setenv("SLURM_CONF", (dir_ / "cluster" / "slurm.conf").c_str(), 1);
        started_ = true;
    }
    void TearDown() override {
        if (started_) {
            const RunResult r = runShell(kClusterScript + " stop " + (dir_ / "cluster").string());
            EXPECT_EQ(r.exitCode, 0) << r.output;
            ::unsetenv("SLURM_CONF");
        }
        if (!dir_.empty()) fs::remove_all(dir_);
    }

    std::string path(const std::string& name) const { return (dir_ / name).string(); }

    // Waits until the queue is empty; false after `seconds`.
    bool waitForEmptyQueue(double seconds) {
        const auto start = Clock::now();
        while (std::chrono::duration<double>(Clock::now() - start).count() < seconds) {
            const RunResult r = runShell("squeue --me --noheader");
            if (r.exitCode == 0 && r.output.empty()) return true;
            std::this_thread::sleep_for(std::chrono::milliseconds(200));
        }
        return false;
    }

    // The film of one render of the same samples, with every core.
    FilmFile renderOnce(const std::string& arguments) {
        const RunResult r =
            runPenumbra("render " + kScene + " -q --no-display -o " + path("once.exr") + " " + arguments);
        EXPECT_EQ(r.exitCode, 0) << r.output;
        return readFilmExr(path("once.exr"));
    }

    // The array job id submit printed.
    static std::string arrayJobOf(const RunResult& submit) {
        const std::string marker = "as Slurm job array ";
        const size_t at = submit.output.find(marker);
        if (at == std::string::npos) return "";
        const size_t begin = at + marker.size();
        return submit.output.substr(begin, submit.output.find('\n', begin) - begin);
    }

    // Waits until `part` holds a checkpoint that is not yet the whole part (its task is
    // mid-render); false after `seconds`.
    bool waitForPartialCheckpoint(const fs::path& part, uint32_t partEnd, double seconds) {
        const auto start = Clock::now();
        while (std::chrono::duration<double>(Clock::now() - start).count() < seconds) {
            if (fs::exists(part)) {
                try {
                    const FilmHeader h = readFilmHeader(part);
                    return h.metadata.endSample < partEnd;
                } catch (const InputError&) {
                }
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
        return false;
    }

    fs::path dir_;
    bool started_ = false;
};

TEST_F(SlurmCluster, EightPartArrayMergesToExactlyOneRender) {
    const std::string options = "--spp 16 --res 64x48";
    const auto start = Clock::now();
    const RunResult submit = runPenumbra("submit " + kScene + " --parts 8 " + options + " -o " +
                                         path("out.exr") + " --cpus-per-task 1 --checkpoint 0");
    ASSERT_EQ(submit.exitCode, 0) << submit.output;
    ASSERT_TRUE(contains(submit.output, "submitted parts 0-7 of 8 as Slurm job array")) << submit.output;
    ASSERT_TRUE(waitForEmptyQueue(300)) << runShell("squeue --me").output;
    const double arraySeconds = std::chrono::duration<double>(Clock::now() - start).count();
    ASSERT_TRUE(fs::exists(path("out.exr"))) << readText(path("out.parts/logs/merge.log"));

    const FilmFile merged = readFilmExr(path("out.exr"));
    EXPECT_EQ(merged.metadata.firstSample, 0u);
    EXPECT_EQ(merged.metadata.endSample, 16u);
    EXPECT_FALSE(merged.metadata.crop);
    const FilmFile once = renderOnce(options);
    EXPECT_TRUE(merged.film.identicalTo(once.film)) << "the merged film differs from one render";
    EXPECT_EQ(merged.metadata.sceneHash, once.metadata.sceneHash);

    const RunResult status = runPenumbra("status " + path("out.exr"));
    EXPECT_EQ(status.exitCode, 0);
    EXPECT_TRUE(contains(status.output, "8 parts: 8 done, 0 partial, 0 started, 0 missing")) << status.output;
    EXPECT_TRUE(contains(status.output, "merged: " + path("out.exr"))) << status.output;
    std::printf("8-part array, submit to merged film: %.1f s (scheduling included)\n", arraySeconds);
}

TEST_F(SlurmCluster, RowBandsMergedAsATreeGiveExactlyOneRender) {
    const std::string options = "--spp 8 --res 64x48";
    const RunResult submit = runPenumbra("submit " + kScene + " --parts 8 --by rows --merge-tree-above 4 " +
                                         options + " -o " + path("out.exr") + " --cpus-per-task 1");
    ASSERT_EQ(submit.exitCode, 0) << submit.output;
    ASSERT_TRUE(contains(submit.output, "submitted the merge of 3 groups")) << submit.output;
    ASSERT_TRUE(waitForEmptyQueue(300)) << runShell("squeue --me").output;
    ASSERT_TRUE(fs::exists(path("out.exr"))) << readText(path("out.parts/logs/merge.log"));
    EXPECT_TRUE(contains(readText(path("out.parts/logs/merge.log")), "merged 8 parts (3 films)"));
    EXPECT_TRUE(readFilmExr(path("out.exr")).film.identicalTo(renderOnce(options).film));
}

// Parts long enough (64 samples each, a checkpoint every 2) that a task is caught mid-render.
const std::string kFaultOptions = "--spp 512 --res 128x96 --pass-size 2";

TEST_F(SlurmCluster, KilledTaskResubmittedWithResumeContinuesItsCheckpoint) {
    const RunResult submit = runPenumbra("submit " + kScene + " --parts 8 " + kFaultOptions + " -o " +
                                         path("out.exr") + " --cpus-per-task 1 --checkpoint 0");
    ASSERT_EQ(submit.exitCode, 0) << submit.output;
    const std::string array = arrayJobOf(submit);
    ASSERT_FALSE(array.empty()) << submit.output;

    // SIGKILL (no chance to write anything) once part 1 has a checkpoint.
    ASSERT_TRUE(waitForPartialCheckpoint(path("out.parts/part-0001.exr"), 128, 120));
    const RunResult kill = runShell("scancel --signal=KILL " + array + "_1");
    ASSERT_EQ(kill.exitCode, 0) << kill.output;
    ASSERT_TRUE(waitForEmptyQueue(300)) << runShell("squeue --me").output;
    EXPECT_FALSE(fs::exists(path("out.exr"))) << "the merge ran though a part had failed";

    // The part is partial, and the merge names it with its range, writing nothing.
    const RunResult status = runPenumbra("status " + path("out.exr"));
    EXPECT_TRUE(contains(status.output, "7 done, 1 partial")) << status.output;
    const RunResult merge = runPenumbra("merge --manifest " + path("out.parts.json"));
    EXPECT_NE(merge.exitCode, 0);
    EXPECT_TRUE(contains(merge.output, "1 of 8 parts are not done")) << merge.output;
    EXPECT_TRUE(contains(merge.output, "part 1 (samples [64, 128)")) << merge.output;
    EXPECT_FALSE(fs::exists(path("out.exr")));

    const RunResult resume = runPenumbra("submit " + kScene + " --parts 8 " + kFaultOptions + " -o " +
                                         path("out.exr") + " --cpus-per-task 1 --checkpoint 0 --resume");
    ASSERT_EQ(resume.exitCode, 0) << resume.output;
    EXPECT_TRUE(contains(resume.output, "submitted parts 1 of 8")) << resume.output;
    ASSERT_TRUE(waitForEmptyQueue(300)) << runShell("squeue --me").output;
    ASSERT_TRUE(fs::exists(path("out.exr"))) << readText(path("out.parts/logs/merge.log"));
    EXPECT_TRUE(contains(readText(path("out.parts/logs/part-0001.log")),
                         "continuing " + path("out.parts/part-0001.exr")));
    EXPECT_TRUE(readFilmExr(path("out.exr")).film.identicalTo(renderOnce(kFaultOptions).film));
}

TEST_F(SlurmCluster, RequeuedTaskContinuesItsCheckpoint) {
    const RunResult submit = runPenumbra("submit " + kScene + " --parts 8 " + kFaultOptions + " -o " +
                                         path("out.exr") + " --cpus-per-task 1 --checkpoint 0");
    ASSERT_EQ(submit.exitCode, 0) << submit.output;
    const std::string array = arrayJobOf(submit);
    ASSERT_FALSE(array.empty()) << submit.output;

    // Requeued as preemption or a node failure would: SIGTERM (the render writes its checkpoint
    // and stops), then the task waits in the queue and runs again.
    ASSERT_TRUE(waitForPartialCheckpoint(path("out.parts/part-0000.exr"), 64, 120));
    const RunResult requeue = runShell("scontrol requeue " + array + "_0");
    ASSERT_EQ(requeue.exitCode, 0) << requeue.output;
    ASSERT_TRUE(waitForEmptyQueue(300)) << runShell("squeue --me").output;
    ASSERT_TRUE(fs::exists(path("out.exr"))) << readText(path("out.parts/logs/merge.log"));
    const std::string log = readText(path("out.parts/logs/part-0000.log"));
    EXPECT_TRUE(contains(log, "restart 1, continuing " + path("out.parts/part-0000.exr"))) << log;
    EXPECT_TRUE(readFilmExr(path("out.exr")).film.identicalTo(renderOnce(kFaultOptions).film));
}

// Names with everything a shell or sbatch acts on (spaces, quotes, $(...), backticks, '#', Slurm's
// '%' patterns) in the output's folder, its name and an --sbatch option: the job array renders,
// the groups and the final merge run, the logs land under the literal names, and no injected
// command runs. A newline is refused before anything is written or submitted.
TEST_F(SlurmCluster, HostileNamesRenderAndMergeWithoutRunningAnything) {
    const fs::path folder = dir_ / "a b'c\"d$(touch INJECTED)e`touch INJECTED`f*g#h%j%a";
    fs::create_directories(folder);
    const fs::path output = folder / "o'u t`touch INJECTED`.exr";
    const std::string options = "--spp 8 --res 32x24";
    const ProgramResult submit =
        runProgram({PENUMBRA_BINARY, "submit", kScene, "--parts", "4", "--merge-tree-above", "2", "--spp",
                    "8", "--res", "32x24", "-o", output.string(), "--cpus-per-task", "1", "--sbatch",
                    "--comment=two words $(touch INJECTED) `touch INJECTED` #x"});
    ASSERT_EQ(submit.exitStatus, 0) << submit.output;
    ASSERT_TRUE(waitForEmptyQueue(300)) << runShell("squeue --me").output;
    const fs::path logs = folder / "o'u t`touch INJECTED`.parts" / "logs";
    ASSERT_TRUE(fs::exists(output)) << readText(logs / "merge.log");
    EXPECT_TRUE(fs::exists(logs / "part-0003.log"));
    EXPECT_TRUE(fs::exists(logs / "group-001.log"));
    EXPECT_TRUE(contains(readText(logs / "merge.log"), "merged 4 parts (2 films)"))
        << readText(logs / "merge.log");
    EXPECT_TRUE(readFilmExr(output).film.identicalTo(renderOnce(options).film));

    const std::string newline = (folder / "x\ntouch INJECTED\n#.exr").string();
    const ProgramResult refused =
        runProgram({PENUMBRA_BINARY, "submit", kScene, "--parts", "2", "-o", newline});
    EXPECT_EQ(refused.exitStatus, 1) << refused.output;
    EXPECT_TRUE(contains(refused.output, "contains a control character")) << refused.output;
    ASSERT_TRUE(waitForEmptyQueue(60));

    // The jobs ran in this process's folder and wrote in `folder`: neither holds what they would have made.
    for (auto it = fs::recursive_directory_iterator(dir_); it != fs::recursive_directory_iterator(); ++it)
        EXPECT_NE(it->path().filename(), "INJECTED") << it->path();
    EXPECT_FALSE(fs::exists(fs::current_path() / "INJECTED"));
    size_t entries = 0;
    for ([[maybe_unused]] const auto& e : fs::directory_iterator(folder)) ++entries;
    EXPECT_EQ(entries, 4u) << "expected the output, its PNG, its manifest and its parts folder only";
}

// A first submit that sbatch refuses (here: a partition the cluster does not have) leaves no
// manifest or script behind, so the same command runs once the option is corrected.
TEST_F(SlurmCluster, AFirstSubmitThatSbatchRefusesLeavesNothingBehind) {
    const std::vector<std::string> submit = {
        PENUMBRA_BINARY, "submit", kScene,          "--parts",         "2", "--spp", "2", "--res",
        "16x12",         "-o",     path("out.exr"), "--cpus-per-task", "1"};
    std::vector<std::string> wrongPartition = submit;
    wrongPartition.insert(wrongPartition.end(), {"--partition", "no-such-partition"});
    const ProgramResult refused = runProgram(wrongPartition);
    EXPECT_EQ(refused.exitStatus, 1) << refused.output;
    EXPECT_TRUE(contains(refused.output, "sbatch")) << refused.output;
    EXPECT_FALSE(fs::exists(path("out.parts.json")));
    EXPECT_FALSE(fs::exists(path("out.parts")));
    const ProgramResult accepted = runProgram(submit);
    ASSERT_EQ(accepted.exitStatus, 0) << accepted.output;
    ASSERT_TRUE(waitForEmptyQueue(300)) << runShell("squeue --me").output;
    EXPECT_TRUE(fs::exists(path("out.exr"))) << readText(path("out.parts/logs/merge.log"));
}

}  // namespace
}  // namespace penumbra
