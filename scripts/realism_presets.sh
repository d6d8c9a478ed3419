#!/usr/bin/env bash
# Realism of the full model against static-only on every synthetic preset:
# makes each scene like the README's default (160x120, 60 frames, detail
# 0.3), trains `full` and `static_only` from one shared Stage-1 model per
# scene and seed list (scripts/ablations.sh), then checks the realism
# targets per preset (scripts/realism_targets.py -> OUT/targets.md).
# Also draws each scene's water twice more (es_synth --water_seed 2, 3)
# and measures those draws like a model (es_compare -> OUT/<preset>/oracle):
# the figures of a perfect model of the water's statistics. Re-running
# skips what is done.
#
#   scripts/realism_presets.sh [--out DIR] [--seeds "0 1 2"]
#       [--presets "waterfall stream fountain droplets pathtraced"]
#       [--train_flags "es_train flags"] [-- extra eulersplat flags]
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/lib/options.sh

out=out/realism
seeds="0 1 2"
presets="waterfall stream fountain droplets pathtraced"
train_flags=""
parse_options "out seeds presets train_flags" "--" "$@"
require_apps es_synth

for preset in $presets; do
  scene=$out/scenes/$preset
  if [[ ! -d $scene/sparse/0 ]]; then
    echo "[realism] generating $scene"
    build/bin/es_synth --out "$scene" --preset "$preset" --frames 60 \
      --width 160 --height 120 --detail 0.3 --num_points 2000
  fi
  for draw in 2 3; do
    other=$out/scenes/${preset}_water$draw
    if [[ ! -d $other/sparse/0 ]]; then
      build/bin/es_synth --out "$other" --preset "$preset" --frames 60 \
        --width 160 --height 120 --detail 0.3 --num_points 2000 \
        --water_seed "$draw"
    fi
    if [[ ! -f $out/$preset/oracle/w$draw/compare.json ]]; then
      build/bin/es_compare --scene "$scene" --other "$other" \
        --out "$out/$preset/oracle/w$draw"
    fi
  done
  bash scripts/ablations.sh --scene "$scene" --out "$out/$preset" \
    --seeds "$seeds" --variants "full static_only" \
    --train_flags "$train_flags" -- "${rest[@]}"
done
# shellcheck disable=SC2086
python3 scripts/realism_targets.py "$out" $presets
