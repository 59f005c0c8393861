#!/usr/bin/env python3
"""Every C++ file of the tree is formatted as the repository's .clang-format says.

usage: check_format.py ROOT [CLANG_FORMAT]

Runs `clang-format --dry-run --Werror` on every .h and .cpp under ROOT (build folders, .git and
test data left out) and lists the files it would change; exits 1 if there are any. Fix them with
`clang-format -i FILE...`.
"""
import os
import subprocess
import sys

SKIPPED = {".git", "data", "corpus"}


def sources(root):
    for folder, subfolders, files in os.walk(root):
        subfolders[:] = sorted(d for d in subfolders if d not in SKIPPED and not d.startswith("build"))
        for name in sorted(files):
            if name.endswith((".h", ".cpp")):
                yield os.path.join(folder, name)


def main():
    if len(sys.argv) not in (2, 3):
        print(__doc__, file=sys.stderr)
        return 2
    root = sys.argv[1]
    clang_format = sys.argv[2] if len(sys.argv) == 3 else "clang-format"
    files = list(sources(root))
    unformatted = []
    for path in files:
        result = subprocess.run([clang_format, "--dry-run", "--Werror", path], capture_output=True, text=True)
        if result.returncode != 0:
            unformatted.append(os.path.relpath(path, root))
    if not files:
        print(f"check_format.py: no C++ files under {root}", file=sys.stderr)
        return 1
    if unformatted:
        print(f"{len(unformatted)} of {len(files)} files are not formatted as .clang-format says "
              f"(clang-format -i FILE... fixes them):", file=sys.stderr)
        for path in unformatted:
            print(f"  {path}", file=sys.stderr)
        return 1
    print(f"{len(files)} files formatted as .clang-format says")
    return 0


if __name__ == "__main__":
    sys.exit(main())
