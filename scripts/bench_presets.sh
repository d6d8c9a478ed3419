#!/usr/bin/env bash
# Run time against error: runs the eulersplat driver with each preset at a
# few iteration budgets (Stage 1 and Stage 3 iterations = the budget, V
# pretraining = half of it, no videos), then tabulates wall time, held-out
# and water PSNR and every realism figure es_eval reports, and draws each
# against wall time into DOCS/bench_presets_<metric>.png (es_plot).
#
#   scripts/bench_presets.sh [--scene DIR] [--out DIR] [--docs DIR]
#                            [--presets "quick paper"]
#                            [--budgets "50 100 200 300"] [--plot_only]
#
# Defaults: the default scene (out/default_scene, made by
# scripts/run_default.sh), runs in out/bench_presets, figures and tables in
# docs/benchmarks. The default run is short (eight runs of at most 300
# iterations per stage, four points per curve); raise --budgets for the
# real curve. Re-running skips finished runs. --plot_only redraws the
# figures from the tables already in DOCS, without running anything.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/lib/options.sh

scene=out/default_scene
out=out/bench_presets
docs=docs/benchmarks
presets="quick paper"
budgets="50 100 200 300"
plot_only=0
parse_options "scene out docs presets budgets" "plot_only" "$@"
for b in $budgets; do
  [[ "$b" =~ ^[1-9][0-9]*$ ]] || {
    echo "bench_presets.sh: --budgets: '$b' is not a positive integer" >&2
    exit 2; }
done
if ((!plot_only)) && [[ ! -d "$scene/sparse/0" ]]; then
  echo "bench_presets.sh: $scene has no sparse/0; run scripts/run_default.sh" \
       "first or give --scene" >&2
  exit 1
fi
tools="eulersplat es_plot"
((plot_only)) && tools=es_plot
# shellcheck disable=SC2086
require_apps $tools
if ((plot_only)); then
  for preset in $presets; do
    [[ -f "$docs/bench_presets_$preset.csv" ]] || {
      echo "bench_presets.sh: --plot_only: $docs/bench_presets_$preset.csv" \
           "missing; run without --plot_only first" >&2
      exit 1; }
  done
else
  mkdir -p "$out" "$docs"

  set -- $presets
  num_runs=$(( $# * $(wc -w <<< "$budgets") ))
  k=0
  for preset in $presets; do
    for budget in $budgets; do
      k=$((k + 1))
      run="$out/${preset}_$budget"
      if [[ -f "$run/wall_seconds" && -f "$run/eval/eval.json" ]]; then
        echo "[bench $k/$num_runs] $preset, budget $budget: done before"
        continue
      fi
      echo "[bench $k/$num_runs] $preset, budget $budget -> $run"
      rm -rf "$run"
      start=$(date +%s.%N)
      build/bin/eulersplat --scene "$scene" --out "$run" --preset "$preset" \
        --static_iterations "$budget" --joint_iterations "$budget" \
        --flow_iterations $(( (budget + 1) / 2 )) --noanimate \
        > "$run.log" 2>&1 || { tail -20 "$run.log" >&2; exit 1; }
      python3 -c "import sys; print(float(sys.argv[2]) - float(sys.argv[1]))" \
        "$start" "$(date +%s.%N)" > "$run/wall_seconds"
    done
  done

  # One table per preset: budget, wall seconds, then every number in
  # eval.json (nested keys joined with '.'), so metrics added later are
  # picked up; a run without a key leaves the cell empty.
  python3 - "$out" "$docs" $presets -- $budgets <<'PY'
import json, pathlib, sys
out, docs = pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2])
split = sys.argv.index("--")
presets, budgets = sys.argv[3:split], sys.argv[split + 1:]

def numbers(value, prefix=""):
    if isinstance(value, dict):
        for key, v in value.items():
            yield from numbers(v, prefix + key + ".")
    elif isinstance(value, (int, float)) and not isinstance(value, bool):
        yield prefix[:-1], value

for preset in presets:
    rows = []
    for budget in budgets:
        run = out / f"{preset}_{budget}"
        row = {"budget": int(budget),
               "wall_seconds": float((run / "wall_seconds").read_text())}
        row.update(numbers(json.loads((run / "eval" / "eval.json").read_text())))
        rows.append(row)
    columns = ["budget", "wall_seconds"] + sorted(
        {k for r in rows for k in r} - {"budget", "wall_seconds"})
    with open(docs / f"bench_presets_{preset}.csv", "w") as f:
        f.write(",".join(columns) + "\n")
        for r in rows:
            f.write(",".join("" if r.get(c) is None else repr(r[c])
                             for c in columns) + "\n")
PY
fi

# Water PSNR, PSNR and every realism figure (any eval.json key under
# "realism"), each against wall time, one curve per preset.
tables="" labels=""
for preset in $presets; do
  tables+="${tables:+,}$docs/bench_presets_$preset.csv"
  labels+="${labels:+,}$preset"
done
metrics="held_out.psnr_water held_out.psnr loop_seam.score"
metrics+=" $(head -qn1 $docs/bench_presets_*.csv | tr ',' '\n' \
  | grep '^realism\.' | sort -u | tr '\n' ' ' || true)"

# What a reader needs on each figure: the metric in words (name, for the
# title), its axis label with the unit, and which way is better.
describe() {
  local metric=$1 region what
  better=""
  case "$metric" in
    held_out.psnr) name="Held-out PSNR"; label="PSNR (dB)"
      better="higher is better" ;;
    held_out.psnr_water) name="Held-out PSNR in the water"
      label="PSNR in the water (dB)"; better="higher is better" ;;
    held_out.ssim) name="Held-out SSIM"; label="SSIM (0 to 1)"
      better="higher is better" ;;
    held_out.ssim_water) name="Held-out SSIM in the water"
      label="SSIM in the water (0 to 1)"; better="higher is better" ;;
    loop_seam.score) name="Loop seam"
      label="change across the seam / within the loop"
      better="1 = seamless, higher = a jump" ;;
    realism.*)
      region=${metric#realism.}; region=${region%%.*}
      what=${metric##*.}
      case "$what" in
        *_ratio) name="Realism: $region ${what%_ratio}"
          label="ratio to the input video"; better="1 = like the input" ;;
        distance_*) name="Realism: $region patch distance"
          label="distance to the input (${what#distance_})"
          better="lower is better" ;;
        *) name=$metric; label=$metric ;;
      esac ;;
    *) name=$metric; label=$metric ;;
  esac
}

# The budgets the tables hold (one point per run), for the x label.
points=$(for preset in $presets; do
  tail -n+2 "$docs/bench_presets_$preset.csv"; done \
  | cut -d, -f1 | sort -nu | paste -sd, - | sed 's/,/, /g')
for metric in $metrics; do
  # A metric some preset's table lacks is skipped, not an error.
  missing=0
  for preset in $presets; do
    head -n1 "$docs/bench_presets_$preset.csv" | tr ',' '\n' \
      | grep -qx "$metric" || missing=1
  done
  if ((missing)); then
    echo "[bench] $metric: not in every table, skipped"
    continue
  fi
  describe "$metric"
  build/bin/es_plot --csv "$tables" --labels "$labels" --x wall_seconds \
    --y "$metric" --y_label "$label" \
    --x_label "wall time of the whole run (s); one point per budget: $points iterations" \
    --title "$name against run time${better:+ ($better)}" \
    --out "$docs/bench_presets_${metric//./_}.png"
done
echo "[bench] tables and figures in $docs"
