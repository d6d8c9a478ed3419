#!/usr/bin/env python3
"""Tabulates scripts/ablations.sh runs: OUT/<variant>/seed*/{model/metrics.json,
eval/eval.json} -> OUT/ablations.md (markdown, mean +- std over seeds) and
OUT/ablations.json (every number).

    scripts/ablation_table.py OUT VARIANT...
"""
import json
import statistics
import sys

from lib.table_args import out_and_names


def realism(region, key):
    """Getter of one realism figure (es_eval's "realism" block)."""
    def get(m, e):
        r = e.get("realism")
        return r[region][key] if r else None
    return get


COLUMNS = [  # (header, getter over (metrics, eval), format)
    ("PSNR", lambda m, e: e["held_out"]["psnr"], "{:.2f}"),
    ("SSIM", lambda m, e: e["held_out"]["ssim"], "{:.3f}"),
    ("water PSNR", lambda m, e: e["held_out"]["psnr_water"], "{:.2f}"),
    ("water SSIM", lambda m, e: e["held_out"]["ssim_water"], "{:.3f}"),
    ("motion rel. EPE",
     lambda m, e: e["motion_gt"]["rel_epe"] if e.get("motion_gt") else None,
     "{:.3f}"),
    ("water detail", realism("water", "detail_ratio"), "{:.2f}"),
    ("water motion", realism("water", "motion_ratio"), "{:.2f}"),
    ("water dist. 2D", realism("water", "distance_2d"), "{:.4f}"),
    ("water dist. 3D", realism("water", "distance_3d"), "{:.4f}"),
    ("static detail", realism("static", "detail_ratio"), "{:.2f}"),
    ("static motion", realism("static", "motion_ratio"), "{:.2f}"),
    ("loop seam", lambda m, e: e["loop_seam"]["score"], "{:.3f}"),
    ("train s", lambda m, e: m["seconds"], "{:.0f}"),
]


def load(run):
    with open(run / "model" / "metrics.json") as f:
        metrics = json.load(f)
    with open(run / "eval" / "eval.json") as f:
        evaluation = json.load(f)
    return metrics, evaluation


def cell(values, fmt):
    values = [v for v in values if v is not None]
    if not values:
        return "n/a"
    text = fmt.format(statistics.mean(values))
    if len(values) > 1:
        text += " ± " + fmt.format(statistics.stdev(values))
    return text


def main():
    out, names = out_and_names(__doc__)
    rows, everything = [], {}
    for variant in names:
        runs = sorted((out / variant).glob("seed*"))
        if not runs:
            sys.exit(f"{out / variant}: no runs")
        loaded = [load(r) for r in runs]
        everything[variant] = {
            r.name: {h: get(m, e) for h, get, _ in COLUMNS}
            for r, (m, e) in zip(runs, loaded)}
        rows.append([variant, str(len(runs))] + [
            cell([get(m, e) for m, e in loaded], fmt)
            for _, get, fmt in COLUMNS])
    header = ["variant", "seeds"] + [h for h, _, _ in COLUMNS]
    lines = ["| " + " | ".join(header) + " |",
             "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(r) + " |" for r in rows]
    (out / "ablations.md").write_text("\n".join(lines) + "\n")
    (out / "ablations.json").write_text(json.dumps(everything, indent=2))
    print("\n".join(lines))


if __name__ == "__main__":
    main()
