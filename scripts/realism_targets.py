#!/usr/bin/env python3
"""Checks the realism targets per preset from scripts/realism_presets.sh
runs: OUT/<preset>/{full,static_only}/seed*/eval/eval.json and
OUT/<preset>/static/flow_metrics.json -> OUT/targets.md (mean over seeds;
a target holds when the mean meets it). Where OUT/<preset>/oracle/*/
compare.json exist (es_compare of other draws of the scene's water), a
second table gives the same figures for those draws: what a model scores
that gets the water's statistics right but not its droplets.

The motion target compares V after joint training with Stage 2's V on the
same points, the joint model's water Gaussians (eval.json's
motion_gt.reference, which the driver has es_eval measure); the figure at
Stage 1's water Gaussians (flow_metrics.json) is shown beside it, and used
where the reference is missing.

    scripts/realism_targets.py OUT PRESET...
"""
import json
import statistics
import sys

from lib.table_args import out_and_names


def evals(out, preset, variant):
    runs = sorted((out / preset / variant).glob("seed*/eval/eval.json"))
    return [json.loads(r.read_text()) for r in runs]


def mean(values):
    values = [v for v in values if v is not None]
    return statistics.mean(values) if values else None


def fmt(v, spec="{:.2f}"):
    return "n/a" if v is None else spec.format(v)


def check(ok):
    return "n/a" if ok is None else ("yes" if ok else "**no**")


def table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    return lines + ["| " + " | ".join(r) + " |" for r in rows]


def water(e, key):
    return e["realism"]["water"][key]


def against_static(runs, static):
    """Water PSNR gain and 2D / 3D distance ratios of `runs` (eval.json or
    compare.json contents) over the static-only runs, means over each."""
    gain = mean([r["held_out"]["psnr_water"] for r in runs]) - mean(
        [s["held_out"]["psnr_water"] for s in static])
    d2, d3 = (mean([water(r, k) for r in runs]) /
              mean([water(s, k) for s in static])
              for k in ("distance_2d", "distance_3d"))
    return gain, d2, d3


def oracle_row(preset, draws, static):
    """The targets' figures for other draws of the water against the same
    static-only runs."""
    gain, d2, d3 = against_static(draws, static)
    return [preset, str(len(draws)),
            fmt(mean([water(d, "detail_ratio") for d in draws])),
            fmt(mean([water(d, "motion_ratio") for d in draws])),
            fmt(mean([d["realism"]["static"]["detail_ratio"]
                      for d in draws])),
            f"{gain:+.2f} dB", f"{d2:.2f} / {d3:.2f}"]


def main():
    out, names = out_and_names(__doc__)
    header = ["preset", "seeds", "water detail (>= 0.85)",
              "water motion (0.8-1.25)", "static detail (>= 0.9)",
              "water PSNR full - static (>= 1.5)",
              "water dist. 2D / 3D full / static (<= 0.5)",
              "rel. EPE flow init (Stage 1's / joint's points) -> joint",
              "loop seam (<= 1.3)"]
    rows, oracle_rows = [], []
    for preset in names:
        full = evals(out, preset, "full")
        static = evals(out, preset, "static_only")
        if not full or not static:
            sys.exit(f"{out / preset}: missing full or static_only runs")
        detail = mean([water(e, "detail_ratio") for e in full])
        motion = mean([water(e, "motion_ratio") for e in full])
        static_detail = mean([e["realism"]["static"]["detail_ratio"]
                              for e in full])
        gain, d2, d3 = against_static(full, static)
        joint_epe = mean([e["motion_gt"]["rel_epe"] if e["motion_gt"]
                          else None for e in full])
        flow = out / preset / "static" / "flow_metrics.json"
        init_epe_stage1 = (json.loads(flow.read_text()).get("rel_epe_gt")
                           if flow.exists() else None)
        references = [e["motion_gt"].get("reference") if e["motion_gt"]
                      else None for e in full]
        init_epe_joint = (mean([r["rel_epe"] for r in references])
                          if all(references) else None)
        init_epe = (init_epe_joint if init_epe_joint is not None
                    else init_epe_stage1)
        seam = mean([e["loop_seam"]["score"] for e in full])
        epe_ok = (None if joint_epe is None or init_epe is None else
                  joint_epe <= init_epe and
                  (preset != "waterfall" or joint_epe <= 0.35))
        rows.append([
            preset, str(len(full)),
            f"{fmt(detail)} {check(detail is not None and detail >= 0.85)}",
            f"{fmt(motion)} {check(motion is not None and 0.8 <= motion <= 1.25)}",
            f"{fmt(static_detail)} "
            f"{check(static_detail is not None and static_detail >= 0.9)}",
            f"{gain:+.2f} dB {check(gain >= 1.5)}",
            f"{d2:.2f} / {d3:.2f} {check(d2 <= 0.5 and d3 <= 0.5)}",
            f"{fmt(init_epe_stage1, '{:.3f}')} / "
            f"{fmt(init_epe_joint, '{:.3f}')} -> "
            f"{fmt(joint_epe, '{:.3f}')} {check(epe_ok)}",
            f"{fmt(seam)} {check(seam is not None and seam <= 1.3)}"])
        draws = [json.loads(r.read_text()) for r in
                 sorted((out / preset / "oracle").glob("*/compare.json"))]
        if draws:
            oracle_rows.append(oracle_row(preset, draws, static))
    lines = table(header, rows)
    if oracle_rows:
        lines += ["", "Another draw of the same water (es_compare):", ""]
        lines += table(["preset", "draws", "water detail", "water motion",
                        "static detail",
                        "water PSNR draw - static_only",
                        "water dist. 2D / 3D draw / static_only"],
                       oracle_rows)
    (out / "targets.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
