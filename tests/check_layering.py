#!/usr/bin/env python3
"""Checks the library's folder layering: a file may include headers of its own folder and of the
folders below it, never of a folder above it or beside it (materials, cameras, lights and media share a
layer and do not include one another). Exits 1 and names every offending include otherwise.

    check_layering.py SOURCE_ROOT [--report]

--report also prints each folder's line count, its share of the library and what it includes.
"""
import pathlib
import re
import sys

# Lowest first; folders in one tuple share a layer.
LAYERS = [("core",), ("textures",), ("geometry",), ("materials", "cameras", "lights", "media"), ("scenes",), ("formats",), ("accel",), ("film",),
          ("renderer",), ("tools",)]
RANK = {folder: rank for rank, folders in enumerate(LAYERS) for folder in folders}
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"/]+)/[^"]+"', re.MULTILINE)


def main() -> int:
    root = pathlib.Path(sys.argv[1])
    report = "--report" in sys.argv[2:]
    violations, lines, includes = [], {}, {}
    for folder in RANK:
        for path in sorted((root / folder).rglob("*")):
            if path.suffix not in (".h", ".cpp"):
                continue
            text = path.read_text(encoding="utf-8", errors="replace")
            lines[folder] = lines.get(folder, 0) + text.count("\n")
            for match in INCLUDE.finditer(text):
                target = match.group(1)
                if target not in RANK:
                    continue  # not one of the library's folders
                includes.setdefault(folder, set()).add(target)
                if target != folder and RANK[target] >= RANK[folder]:
                    line = text.count("\n", 0, match.start()) + 1
                    where = "beside" if RANK[target] == RANK[folder] else "above"
                    violations.append(f"{path.relative_to(root)}:{line}: includes {target}/, a folder {where} {folder}/")
    if report:
        total = sum(lines.values())
        for folder in RANK:
            if folder in lines:
                below = ", ".join(sorted(includes.get(folder, set()) - {folder}, key=RANK.get)) or "nothing"
                print(f"{folder:10} {lines[folder]:6} lines {100 * lines[folder] / total:5.1f}%  includes {below}")
    for v in violations:
        print(v)
    if not lines:
        print(f"no library folders under {root}")
        return 1
    return 1 if violations else 0


if __name__ == "__main__":
    sys.exit(main())
