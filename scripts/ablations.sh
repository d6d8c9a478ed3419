#!/usr/bin/env bash
# The paper's ablations on one scene: the full model and each variant of
# es_train (--static_only, --no_motion_field, --no_flow_init, --no_residual,
# --no_random_start) trained from ONE shared Stage-1 model and pretrained V,
# each evaluated by es_eval, then tabulated into OUT/ablations.md (and
# OUT/ablations.json). Re-running skips finished variants.
#
#   scripts/ablations.sh [--scene DIR] [--out DIR] [--preset quick|paper]
#                        [--seeds "0 1 2"] [--variants "full static_only"]
#                        [--train_flags "es_train flags for every variant"]
#                        [-- extra eulersplat flags]
#
# Defaults: the README's default scene (out/default_scene, made by
# scripts/run_default.sh), out/ablations, quick preset, seed 0. With several
# seeds every variant is trained once per seed (es_train --seed: frame order
# and start times) and the table gives mean and spread.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/lib/options.sh

scene=out/default_scene
out=out/ablations
preset=quick
seeds=0
variants="full static_only no_motion_field no_flow_init no_residual
          no_random_start"
train_flags=""
parse_options "scene out preset seeds variants train_flags" "--" "$@"
if [[ ! -d "$scene/sparse/0" ]]; then
  echo "ablations.sh: $scene has no sparse/0; run scripts/run_default.sh" \
       "first or give --scene" >&2
  exit 1
fi
require_apps eulersplat

read -r -a variants <<< "$(echo $variants)"
for seed in $seeds; do
  for variant in "${variants[@]}"; do
    flags="--seed $seed $train_flags"
    [[ $variant != full ]] && flags="--$variant $flags"
    echo "[ablations] $variant, seed $seed"
    build/bin/eulersplat --scene "$scene" --out "$out/$variant/seed$seed" \
      --preset "$preset" --static_dir "$out/static" --animate=false \
      --train_flags="$flags" "${rest[@]}"
  done
done

python3 scripts/ablation_table.py "$out" "${variants[@]}"
echo "[ablations] table: $out/ablations.md"
