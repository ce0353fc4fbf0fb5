#!/usr/bin/env python3
"""Checks a built site: every relative href/src in the MkDocs pages names a file that exists,
and every #fragment names an id (or name) in its target page. `mkdocs build --strict` (MkDocs
1.4) checks links between Markdown files but not anchors, and not links into the Doxygen
output; this does both. Usage: check_links.py SITE_DIR. Exit 1 and one line per broken link."""
import os
import sys
from html.parser import HTMLParser
from urllib.parse import unquote, urlsplit


class _Page(HTMLParser):
    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.ids = set()
        self.links = []

    def handle_starttag(self, tag, attrs):
        for name, value in attrs:
            if value is None:
                continue
            if name in ("id", "name"):
                self.ids.add(value)
            elif name in ("href", "src"):
                self.links.append(value)


def _parse(path, cache):
    if path not in cache:
        page = _Page()
        with open(path, encoding="utf-8", errors="replace") as f:
            page.feed(f.read())
        cache[path] = page
    return cache[path]


def main(site):
    site = os.path.abspath(site)
    cache, broken, checked = {}, [], 0
    for root, dirs, files in os.walk(site):
        if os.path.relpath(root, site).split(os.sep)[0] == "api":
            continue  # Doxygen's own pages: its generator keeps their links consistent
        for name in files:
            if not name.endswith(".html") or name == "404.html":
                continue
            source = os.path.join(root, name)
            for link in _parse(source, cache).links:
                parts = urlsplit(link)
                if parts.scheme or parts.netloc or link.startswith(("mailto:", "javascript:", "data:")):
                    continue
                target = source if not parts.path else os.path.normpath(
                    os.path.join(os.path.dirname(source), unquote(parts.path)))
                if os.path.isdir(target):
                    target = os.path.join(target, "index.html")
                checked += 1
                where = os.path.relpath(source, site)
                if not target.startswith(site + os.sep) or not os.path.exists(target):
                    broken.append("%s: %s: no such file" % (where, link))
                elif parts.fragment and target.endswith(".html") and \
                        unquote(parts.fragment) not in _parse(target, cache).ids:
                    broken.append("%s: %s: no anchor #%s in %s" % (
                        where, link, parts.fragment, os.path.relpath(target, site)))
    for line in broken:
        print(line)
    print("check_links: %d links checked, %d broken" % (checked, len(broken)))
    return 1 if broken or checked == 0 else 0


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: check_links.py SITE_DIR")
    sys.exit(main(sys.argv[1]))
