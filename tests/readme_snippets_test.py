#!/usr/bin/env python3
"""Runs every fenced block of the project's Markdown files against the built program.

Usage: readme_snippets_test.py SOURCE_DIR PENUMBRA_BINARY [FILE.md ...]

What a block's info string (the word after the opening fence) says is done with it:
  sh                a command block: run with bash -euo pipefail in a scratch folder that holds
                    the checkout's scenes/ (as `scenes`), with the built `penumbra` first on PATH;
                    the blocks of one file run in order in the same folder, so a block may use
                    what an earlier one wrote. It must exit 0.
  jsonc, json       a complete scene: written to a file and rendered (8x8 pixels, 1 spp);
                    relative mesh paths are resolved against scenes/, as for the example scenes.
  jsonc fragment    part of a scene (e.g. one "materials" object): wrapped in braces with a
                    camera (unless it gives its own) and rendered the same way, so every key in it
                    must load.
  text              output, a synopsis or any other text: not run.
  sh not-run REASON a command that cannot run inside the test suite (it installs packages,
                    builds the project or runs a benchmark); the reason is required.
Any other info string, or none, fails the test: every block either runs or says why it does not.
With PENUMBRA_SNIPPETS_KEEP=DIR set, the convergence studies the README's commands ran are kept in
DIR (their convergence.json files, by folder) for docs_figures_test.py.
"""

import os
import re
import shutil
import subprocess
import sys
import tempfile

FENCE = re.compile(r"^(\s*)```(.*)$")


def blocks_of(path):
    """Yields (line number, info string, text) of each fenced block in a Markdown file."""
    with open(path, encoding="utf-8") as f:
        lines = f.read().split("\n")
    i = 0
    while i < len(lines):
        m = FENCE.match(lines[i])
        if not m:
            i += 1
            continue
        indent, info = m.group(1), m.group(2).strip()
        start = i + 1
        body = []
        i += 1
        while i < len(lines) and not re.match(r"^\s*```\s*$", lines[i]):
            body.append(lines[i][len(indent):] if lines[i].startswith(indent) else lines[i])
            i += 1
        if i == len(lines):
            raise SystemExit(f"{path}:{start}: fenced block is never closed")
        yield start, info, "\n".join(body) + "\n"
        i += 1


def markdown_files(source):
    # tests/data holds fixtures, among them a file of blocks this test must fail on.
    fixtures = os.path.join(source, "tests", "data")
    for root, dirs, files in os.walk(source):
        dirs[:] = sorted(d for d in dirs if not d.startswith(".") and not d.startswith("build") and d != "out"
                         and os.path.join(root, d) != fixtures)
        for name in sorted(files):
            if name.endswith(".md"):
                yield os.path.join(root, name)


def run(cmd, cwd, env, where, failures):
    result = subprocess.run(cmd, cwd=cwd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if result.returncode != 0:
        failures.append(f"{where}: exited with status {result.returncode}:\n{result.stdout[-3000:]}")
        return False
    return True


def render_scene(text, workdir, env, where, failures, wrap):
    if wrap:
        # A fragment that gives its own camera (e.g. a shutter for motion) keeps it.
        camera = "" if re.search(r'^\s*"camera"\s*:', text, re.M) else \
            ',\n"camera": {"look_from": [0, 0, 5], "look_at": [0, 0, 0], "fov": 40}'
        text = "{\n" + text + camera + "\n}\n"
    scene = os.path.join(workdir, "scenes", "snippet.json")
    with open(scene, "w", encoding="utf-8") as f:
        f.write(text)
    ok = run(["penumbra", "render", scene, "--res", "8x8", "--spp", "1", "--no-display", "--quiet",
              "-o", os.path.join(workdir, "snippet.exr")], workdir, env, where, failures)
    os.remove(scene)
    return ok


def keep_outputs(md, source, workdir):
    """The convergence studies' results of the README's commands (their out/*/convergence.json), for
    docs_figures_test.py: copied to $PENUMBRA_SNIPPETS_KEEP when it is set."""
    keep = os.environ.get("PENUMBRA_SNIPPETS_KEEP")
    if not keep or os.path.relpath(md, source) != "README.md":
        return
    shutil.rmtree(keep, ignore_errors=True)
    out = os.path.join(workdir, "out")
    for root, _, files in os.walk(out):
        if "convergence.json" in files:
            target = os.path.join(keep, os.path.relpath(root, out))
            os.makedirs(target, exist_ok=True)
            shutil.copy(os.path.join(root, "convergence.json"), target)


def main():
    source, binary = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
    files = [os.path.abspath(p) for p in sys.argv[3:]] or list(markdown_files(source))
    bindir = tempfile.mkdtemp(prefix="penumbra-bin-")
    os.symlink(binary, os.path.join(bindir, "penumbra"))
    env = dict(os.environ, PATH=bindir + os.pathsep + os.environ.get("PATH", ""))
    failures, counts = [], {"run": 0, "scene": 0, "not run": 0}
    try:
        for md in files:
            rel = os.path.relpath(md, source)
            workdir = tempfile.mkdtemp(prefix="penumbra-snippets-")
            try:
                # A copy of scenes/ (the examples and their meshes), so that snippets may write there.
                shutil.copytree(os.path.join(source, "scenes"), os.path.join(workdir, "scenes"),
                                ignore=shutil.ignore_patterns("*.cpp", "*.h", "CMakeLists.txt"))
                for line, info, text in blocks_of(md):
                    where = f"{rel}:{line}"
                    words = info.split()
                    kind = words[0] if words else ""
                    if kind == "text":
                        counts["not run"] += 1
                    elif kind == "sh" and len(words) >= 2 and words[1] == "not-run":
                        if len(words) < 3:
                            failures.append(f"{where}: 'sh not-run' without a reason")
                        counts["not run"] += 1
                    elif kind == "sh" and len(words) == 1:
                        print(f"{where}: running\n{text}", flush=True)
                        run(["bash", "-euo", "pipefail", "-c", text], workdir, env, where, failures)
                        counts["run"] += 1
                    elif kind in ("json", "jsonc") and len(words) == 1:
                        render_scene(text, workdir, env, where, failures, wrap=False)
                        counts["scene"] += 1
                    elif kind in ("json", "jsonc") and words[1:] == ["fragment"]:
                        render_scene(text, workdir, env, where, failures, wrap=True)
                        counts["scene"] += 1
                    else:
                        failures.append(f"{where}: fenced block with info string '{info}': mark it 'sh', 'jsonc', "
                                        f"'jsonc fragment', 'text' or 'sh not-run REASON' (tests/readme_snippets_test.py)")
            finally:
                keep_outputs(md, source, workdir)
                shutil.rmtree(workdir, ignore_errors=True)
    finally:
        shutil.rmtree(bindir, ignore_errors=True)
    print(f"{counts['run']} command blocks run, {counts['scene']} scenes rendered, {counts['not run']} blocks marked "
          f"as not run, in {len(files)} files")
    for f in failures:
        print(f"FAILED {f}", file=sys.stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
