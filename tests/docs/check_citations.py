#!/usr/bin/env python3
"""Papers are cited in the sources as author, year, section and equation
("Novak et al. 2012 (VRL), section 4.1, eq. 9"), never as a file path: the paper files
(virtual-ray-lights.txt, ../shared/papers/...) are not part of the repository.

Scans the C/C++/Python/CMake/shell sources and the Markdown pages (docs/, README.md) under
SOURCE_DIR (not build trees) and fails, naming file and line, on a `.txt` name that looks like a paper file: a hyphenated name
(`some-paper-title.txt`) that is not a file of the repository, or any path through a `papers/`
folder. Usage: check_citations.py SOURCE_DIR."""
import os
import re
import sys

SOURCES = (".c", ".h", ".cc", ".cpp", ".in", ".py", ".sh", ".cmake", ".md")
PAPER = re.compile(r"(?:[\w.-]*/)?papers/[\w.-]+\.txt|\b[a-z0-9]+(?:-[a-z0-9]+)+\.txt\b")
SKIP_DIRS = {".git", "__pycache__"}


def sources(root):
    for folder, dirs, files in os.walk(root):
        dirs[:] = [d for d in dirs if d not in SKIP_DIRS and not d.startswith(("build", "."))]
        for name in files:
            if name.endswith(SOURCES) or name == "CMakeLists.txt":
                yield os.path.join(folder, name)


def main(root):
    names = set()
    for folder, dirs, files in os.walk(root):
        dirs[:] = [d for d in dirs if d not in SKIP_DIRS and not d.startswith(("build", "."))]
        names.update(files)
    found, scanned = [], 0
    for path in sources(root):
        if os.path.abspath(path) == os.path.abspath(__file__):
            continue  # this script's own examples
        scanned += 1
        with open(path, encoding="utf-8", errors="replace") as f:
            for number, line in enumerate(f, 1):
                for match in PAPER.findall(line):
                    if "papers/" in match or os.path.basename(match) not in names:
                        found.append("%s:%d: cites a paper as a file path (%s): write author, year, "
                                     "section and equation" % (os.path.relpath(path, root), number, match))
    for line in found:
        print(line)
    print("check_citations: %d source files scanned, %d file-path citations" % (scanned, len(found)))
    return 1 if found or scanned == 0 else 0


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: check_citations.py SOURCE_DIR")
    sys.exit(main(sys.argv[1]))
