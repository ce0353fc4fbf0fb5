#!/usr/bin/env bash
# Builds the documentation site into OUT_DIR and checks it (the `docs_site` test):
#   1. mkdocs build --strict (warnings are errors: a missing page or a broken link between pages),
#   2. Doxygen for the public headers into OUT_DIR/api (warnings are errors), and a second
#      Doxygen pass that fails on an undocumented public symbol (type, field, enum value,
#      macro, function) in any public header,
#   3. docsite/check_links.py: every internal link and #anchor of the pages resolves.
# Usage: docsite/build_site.sh OUT_DIR [VBL_CLI [VERSION_HEADER_DIR]]
#   VBL_CLI: the `vbl` binary whose --help texts fill the command-line reference;
#   VERSION_HEADER_DIR: the build tree's include folder holding vbl/vbl_version.h.
# Exits 77 (the test reports "skipped") when mkdocs or doxygen is not installed
# (`./setup.sh test` installs both).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
out="${1:?usage: build_site.sh OUT_DIR [VBL_CLI [VERSION_HEADER_DIR]]}"
cli="${2:-}"
version_dir="${3:-}"
for tool in mkdocs doxygen python3; do
  command -v "$tool" >/dev/null || { echo "build_site: $tool is not installed (apt-get install $tool)"; exit 77; }
done
mkdir -p "$out"
out="$(cd "$out" && pwd)"
cd "$root"
[ -z "$cli" ] || export VBL_CLI="$cli"
# mkdocs writes INFO lines for pages outside the nav; --strict turns every WARNING into a failure
mkdocs build --strict --quiet --config-file mkdocs.yml --site-dir "$out"
{
  cat docsite/Doxyfile
  echo "OUTPUT_DIRECTORY = $out/api"
  if [ -n "$version_dir" ] && [ -f "$version_dir/vbl/vbl_version.h" ]; then
    echo "INPUT += $version_dir/vbl/vbl_version.h"
    echo "STRIP_FROM_PATH += $version_dir"
  fi
} | doxygen -
# Every public symbol has a comment (no header is exempt).
undocumented="$({
  cat docsite/Doxyfile
  echo "EXTRACT_ALL = NO"
  echo "WARN_AS_ERROR = NO"
  echo "GENERATE_HTML = NO"
  echo "OUTPUT_DIRECTORY = $out/.undocumented"
} | doxygen - 2>&1 | grep 'is not documented' || true)"
rm -rf "$out/.undocumented"
if [ -n "$undocumented" ]; then
  echo "$undocumented"
  echo "build_site: public symbols without a comment (the API reference is made from them)"
  exit 1
fi
python3 docsite/check_links.py "$out"
echo "build_site: $out/index.html"
