#!/usr/bin/env bash
# Assembles README.md from the sections in docs/readme/ (in file-name order of the list below).
set -euo pipefail
cd "$(dirname "$0")"
{
  for section in 00-intro vdb volume render vrl output sampling beams surfaces surface_transport_notes materials blue_noise blue_noise_bench blue_noise_media performance pipeline 99-development; do
    [ -f "$section.md" ] || continue
    cat "$section.md"
    echo
  done
} > ../../README.md
