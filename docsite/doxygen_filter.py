#!/usr/bin/env python3
"""Doxygen INPUT_FILTER for libvbl's public headers (docsite/Doxyfile).

The headers document every declaration with plain C comments, written for people reading the
header; this filter lets Doxygen read the same comments without a second comment syntax in the
sources: the file's first comment becomes its @file text, a comment on its own line documents
the declaration below it (`/**`), a comment after code on the same line documents that code
(`/**<`), and section rulers (`/* ---- name ---- */`) stay plain. A `<` that would open an HTML
tag in prose ("<file>") is escaped. A member line declaring several fields with one trailing
comment (`int min[3], max[3]; /* inclusive */`) is split into one declaration per field, each
with that comment (Doxygen would document only the last). Usage: doxygen_filter.py FILE (writes to stdout)."""
import re
import sys


def filter_header(text):
    out, in_comment, seen_first = [], False, False
    for line in text.split("\n"):
        if in_comment:
            end = line.find("*/")
            body, rest = (line, "") if end < 0 else (line[:end], line[end:])
            out.append(_escape(body) + rest)
            in_comment = end < 0
            continue
        start = line.find("/*")
        if start < 0 or line.startswith("//", 0):
            out.append(line)
            continue
        code, comment = line[:start], line[start:]
        if comment.startswith("/* ----"):
            marker = "/*"
        elif comment.startswith("/**"):
            marker = comment[:4] if comment.startswith("/**<") else "/**"
        elif code.strip():
            marker = "/**<"
        elif not seen_first:
            marker = "/** @file\n *"
        else:
            marker = "/**"
        seen_first = True
        plain = "/**<" if comment.startswith("/**<") else ("/**" if comment.startswith("/**") else "/*")
        body = comment[len(plain):]
        end = body.find("*/")
        if end < 0:
            out.append(code + marker + _escape(body))
            in_comment = True
        else:
            out.append(code + marker + _escape(body[:end]) + body[end:])
    return "\n".join(out)


_MULTI = re.compile(r"^(\s*)((?:const\s+)?[A-Za-z_][\w ]*?[\s*]+)([A-Za-z_]\w*(?:\[\w*\])*(?:\s*,\s*[A-Za-z_]\w*(?:\[\w*\])*)+);(\s*)(/\*\*<.*)$")


def split_declarators(text):
    out = []
    for line in text.split("\n"):
        m = _MULTI.match(line)
        if not m:
            out.append(line)
            continue
        indent, type_, names, space, comment = m.groups()
        if not comment.rstrip().endswith("*/"):
            out.append(line)  # a comment continued on the next lines: leave it
            continue
        for name in names.split(","):
            out.append("%s%s%s;%s%s" % (indent, type_, name.strip(), space, comment))
    return "\n".join(out)


def _escape(prose):
    return re.sub(r"<(?=[A-Za-z/])", r"\\<", prose)


if __name__ == "__main__":
    with open(sys.argv[1], encoding="utf-8") as f:
        sys.stdout.write(split_declarators(filter_header(f.read())))
