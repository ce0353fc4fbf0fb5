#!/usr/bin/env bash
# The Cycles race of issues #13 and #14: bench/race_cycles/run.sh [--quick] [race.py options]
# The presets against the alternatives (after a race, on its references): run.sh --presets [...]
# Needs build/bin/vbl and build/samples/cloud.vdb (targets vbl_cli, vbl_sample_cloud), blender,
# python3-openimageio, python3-openvdb and python3-matplotlib (setup.sh's test packages), and the
# Cycles reference kit at ../shared/tools/cycles-reference (relative to the project root).
# Writes bench/results/race_cycles.{csv,txt} (--quick: race_cycles_quick.*) and
# docs/images/race_cycles.png; renders and cached references go to build/race_cycles.
# Not in CI: it measures time. Hours of 2 cores at the defaults (Cycles 256 spp, references 8x the
# budget); the published run used --spp 12 --ref-factor 2.5 --budget 15; --quick is a smoke run.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
kit="$here/../../../shared/tools/cycles-reference"
[ -x "$kit/render.sh" ] || { echo "race_cycles: the Cycles kit is not at $kit" >&2; exit 2; }
if [ "${1:-}" = --presets ]; then shift; exec /usr/bin/python3 "$here/presets.py" "$@"; fi
exec /usr/bin/python3 "$here/race.py" "$@"
