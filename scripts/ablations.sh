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

scene=out/default_scene
out=out/ablations
preset=quick
seeds=0
variants="full static_only no_motion_field no_flow_init no_residual
          no_random_start"
train_flags=""
while [[ $# -gt 0 ]]; do
  case "$1" in
    --scene) scene=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --preset) preset=$2; shift 2 ;;
    --seeds) seeds=$2; shift 2 ;;
    --variants) variants=$2; shift 2 ;;
    --train_flags) train_flags=$2; shift 2 ;;
    --) shift; break ;;
    -h|--help) sed -n '2,16p' "$0"; exit 0 ;;
    *) echo "ablations.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
if [[ ! -d "$scene/sparse/0" ]]; then
  echo "ablations.sh: $scene has no sparse/0; run scripts/run_default.sh" \
       "first or give --scene" >&2
  exit 1
fi
if [[ ! -x build/bin/eulersplat ]]; then
  echo "ablations.sh: build/bin/eulersplat missing; run scripts/setup.sh" >&2
  exit 1
fi

read -r -a variants <<< "$(echo $variants)"
for seed in $seeds; do
  for variant in "${variants[@]}"; do
    flags="--seed $seed $train_flags"
    [[ $variant != full ]] && flags="--$variant $flags"
    echo "[ablations] $variant, seed $seed"
    build/bin/eulersplat --scene "$scene" --out "$out/$variant/seed$seed" \
      --preset "$preset" --static_dir "$out/static" --animate=false \
      --train_flags="$flags" "$@"
  done
done

python3 scripts/ablation_table.py "$out" "${variants[@]}"
echo "[ablations] table: $out/ablations.md"
