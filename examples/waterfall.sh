#!/usr/bin/env bash
# The default scene of the README: a 120-frame 320x240 synthetic waterfall
# with exact poses and ground truth, and a contact sheet of it.
#
#   examples/waterfall.sh [OUT_DIR] [PRESET]  (default /tmp/es_waterfall,
#                                              waterfall; or stream, fountain)
#
# ES_BIN selects the binaries (default build/bin).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bin=${ES_BIN:-$root/build/bin}
out=${1:-/tmp/es_waterfall}
preset=${2:-waterfall}

"$bin/es_synth" --out "$out" --preset "$preset" --frames 120 \
  --width 320 --height 240 --seed 1 --stochasticity 1
"$bin/es_contact_sheet" --scene "$out" --out "${out%/}_sheet.png" --count 8
