// The manifest of a split render (readManifest, as `merge --manifest`, `status` and
// `submit --resume` read it), then the batch scripts submit would write from what reads. Beyond
// the readers' contract, each script must hold only the lines submit writes: a value from the
// manifest that started a line of its own (a command run on the compute node) aborts the run.
// A manifest names its files beside itself, in a folder made for the run: "@DIR@" in the input
// stands for that folder, so that seeds and mutations can name files there.
#include <cstdlib>
#include <string_view>

#include "fuzz/fuzz_input.h"
#include "tools/part_manifest.h"
#include "tools/slurm_batch.h"
#include "tools/split_text.h"

namespace {

// Every line of a batch script starts with one of these (tools/slurm_batch.cpp).
bool isScriptLine(std::string_view line) {
    for (std::string_view start : {"#!/bin/bash", "# penumbra submit: ", "#SBATCH ", "set -euo pipefail",
                                   "case \"${SLURM_ARRAY_TASK_ID", "    ", "esac", "# A requeued",
                                   "resume=()", "if [ -e \"$part\" ]", "echo \"penumbra: part ", "exec '"})
        if (line.starts_with(start)) return true;
    return line.empty();
}

void requireOnlyScriptLines(const std::string& script) {
    for (const std::string& line : penumbra::splitText(script, '\n'))
        if (!isScriptLine(line)) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace penumbra;
    static fuzz::ScratchFile manifest("out.parts.json");
    static const std::string folder = manifest.folder().string();
    std::string text(fuzz::asText(data, size));
    for (size_t at = text.find("@DIR@"); at != std::string::npos; at = text.find("@DIR@", at + folder.size()))
        text.replace(at, 5, folder);
    return fuzz::expectReadOrInputError([&] {
        const std::filesystem::path& path =
            manifest.write(reinterpret_cast<const uint8_t*>(text.data()), text.size());
        const PartManifest m = readManifest(path);
        std::vector<int> all;
        for (size_t i = 0; i < m.parts.size(); ++i) all.push_back(int(i));
        SlurmRequest request;
        requireOnlyScriptLines(renderScript(m, path, request, all));
        if (!m.groups.empty()) requireOnlyScriptLines(groupMergeScript(m, path, request));
        requireOnlyScriptLines(finalMergeScript(m, path, request));
    });
}
