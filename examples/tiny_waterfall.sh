#!/usr/bin/env bash
# A tiny synthetic waterfall (12 frames, 64x48, a few thousand Gaussians)
# that every stage runs through in seconds, plus a contact sheet to look at.
#
#   examples/tiny_waterfall.sh [OUT_DIR]      (default /tmp/es_tiny_waterfall)
#
# ES_BIN selects the binaries (default build/bin).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bin=${ES_BIN:-$root/build/bin}
out=${1:-/tmp/es_tiny_waterfall}

"$bin/es_synth" --out "$out" --preset waterfall --frames 12 \
  --width 64 --height 48 --detail 0.03 --num_points 300 --grid_resolution 12
"$bin/es_contact_sheet" --scene "$out" --out "${out%/}_sheet.png" --count 4
