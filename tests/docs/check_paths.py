#!/usr/bin/env python3
"""Every file or folder a contributor document names exists in the tree.

Checks docs/CONTRIBUTING.md and README.md: each token that looks like a project path
(`libvbl/src/core/`, `plugins/cli/render_options.c`, `tests/<area>/`) or a file name
(`render.c`, `make_cloud.cc`) must exist; a file name is looked up in the folder of its
Layout line (the first token of the line or the line above), next to the document, else anywhere in the
tree. C and JSON examples are skipped.
`<area>`/`<name>` placeholders and `*` match any name; paths under build/, out/ or outside the
project (../) are not checked. Usage: check_paths.py SOURCE_DIR [FILE.md...]. Exit 1 on a
missing path, naming the document and the line."""
import glob
import os
import re
import sys

PATH = re.compile(r"(?<![\w./<>*-])(\.?[A-Za-z0-9_<>*-]+(?:/[A-Za-z0-9_.<>*-]*)+|[A-Za-z0-9_*-]+(?:\.[A-Za-z0-9_-]+)*\.(?:c|h|cc|in|py|sh|json|md|cmake|yml|obj|ocio|txt|csv))(?![\w/.])")
SKIP_PREFIXES = ("build", "build-asan", "out", "..", "http:", "https:", "PREFIX")


def _exists(root, token, folder, document):
    pattern = re.sub(r"<[^>]+>", "*", token)
    candidates = [os.path.join(root, pattern), os.path.join(root, os.path.dirname(document), pattern)]
    if "/" not in token.rstrip("/"):
        if folder:
            candidates.insert(0, os.path.join(root, folder, pattern))
        candidates.append(os.path.join(root, "**", pattern))
    for candidate in candidates:
        for found in glob.glob(candidate, recursive=True):
            first = os.path.relpath(found, root).split(os.sep)[0]
            if not first.startswith(("build", ".git", "out")):  # build outputs do not count
                return True
    return False


def check(root, document):
    missing, checked, folder = [], 0, ""
    in_code, skip_block = False, False
    with open(os.path.join(root, document), encoding="utf-8") as f:
        lines = f.read().split("\n")
    for number, line in enumerate(lines, 1):
        if line.startswith("```"):
            in_code = not in_code
            skip_block = in_code and line.strip() in ("```c", "```json")  # example code, not the tree
            folder = ""
            continue
        if skip_block:
            continue
        if in_code and line and not line[0].isspace():
            first = line.split()[0]
            folder = first if first.endswith("/") else ""
        for token in PATH.findall(line):
            token = token.rstrip(".,;:")
            if token.startswith(SKIP_PREFIXES) or "/" in token and not re.match(r"[\w.<*]", token):
                continue
            if "/" in token and not token.endswith("/") and "." not in os.path.basename(token) \
                    and not os.path.exists(os.path.join(root, token)) and "<" not in token:
                # words joined by a slash ("sample / pdf", "vpl/vrl") are not paths
                if not os.path.isdir(os.path.join(root, token.split("/")[0])):
                    continue
            checked += 1
            if not _exists(root, token, folder, document):
                missing.append("%s:%d: %s does not exist" % (document, number, token))
    return missing, checked


def main(argv):
    if len(argv) < 2:
        sys.exit("usage: check_paths.py SOURCE_DIR [FILE.md...]")
    root = argv[1]
    documents = argv[2:] or ["docs/CONTRIBUTING.md", "README.md"]
    missing, checked = [], 0
    for document in documents:
        m, c = check(root, document)
        missing += m
        checked += c
    for line in missing:
        print(line)
    print("check_paths: %d paths checked in %s, %d missing" % (checked, ", ".join(documents), len(missing)))
    return 1 if missing or checked == 0 else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
