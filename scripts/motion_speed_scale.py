#!/usr/bin/env python3
"""Did joint training teach V the motion, or only change its speed?

Reads es_eval's OUT/motion_gt.csv (the model's V per water Gaussian) and
OUT/motion_gt_reference.csv (--reference_motion's V, e.g. Stage 2's, at the
same points) and prints, as relative EPE (summed |V - truth| over summed
|truth|) and speed ratio (summed |V| over summed |truth|):
  - the model's V and the reference's;
  - the reference scaled uniformly to the model's speed: if this is as
    good as the model, joint training changed V's speed and nothing else;
  - the reference's best uniform scale (searched over --min_scale ..
    --max_scale): how far the reference's speed is from the truth's.
"""
import argparse
import csv
import math
import os
import sys

PROG = "motion_speed_scale.py"


def read_points(path):
    try:
        with open(path, newline="") as f:
            rows = list(csv.DictReader(f))
        points = [([float(r[k]) for k in ("x", "y", "z")],
                   [float(r[k]) for k in ("model_vx", "model_vy", "model_vz")],
                   [float(r[k]) for k in ("true_vx", "true_vy", "true_vz")])
                  for r in rows]
    except (OSError, ValueError, KeyError, TypeError) as e:
        sys.exit(f"{PROG}: {path}: {e}")
    if not points:
        sys.exit(f"{PROG}: {path}: no points")
    return points


def rel_epe(velocities, truths, scale=1.0):
    error = sum(math.dist([scale * c for c in v], t)
                for v, t in zip(velocities, truths))
    return error / sum(math.hypot(*t) for t in truths)


def speed_ratio(velocities, truths):
    return (sum(math.hypot(*v) for v in velocities) /
            sum(math.hypot(*t) for t in truths))


def main():
    parser = argparse.ArgumentParser(
        prog="scripts/" + PROG, description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("eval_dir", help="es_eval's --out folder, evaluated "
                        "with --reference_motion")
    parser.add_argument("--min_scale", type=float, default=0.5,
                        help="smallest scale of the reference searched "
                        "(default 0.5)")
    parser.add_argument("--max_scale", type=float, default=2.0,
                        help="largest scale searched (default 2.0)")
    args = parser.parse_args()
    if not 0 < args.min_scale <= args.max_scale:
        sys.exit(f"{PROG}: need 0 < --min_scale <= --max_scale")
    model = read_points(os.path.join(args.eval_dir, "motion_gt.csv"))
    reference = read_points(
        os.path.join(args.eval_dir, "motion_gt_reference.csv"))
    if [p[0] for p in model] != [p[0] for p in reference]:
        sys.exit(f"{PROG}: {args.eval_dir}: motion_gt.csv and "
                 "motion_gt_reference.csv hold different points")
    truths = [p[2] for p in model]
    v_model = [p[1] for p in model]
    v_ref = [p[1] for p in reference]
    if sum(math.hypot(*t) for t in truths) == 0:
        sys.exit(f"{PROG}: {args.eval_dir}: the true velocity is 0 at "
                 "every point")
    ref_speed = speed_ratio(v_ref, truths)
    to_model = speed_ratio(v_model, truths) / ref_speed if ref_speed else 1.0
    steps = int(round((args.max_scale - args.min_scale) / 0.01))
    scales = [args.min_scale + 0.01 * k for k in range(steps + 1)]
    best = min(scales, key=lambda s: rel_epe(v_ref, truths, s))

    print(f"{len(truths)} points")
    print(f"model V               rel. EPE {rel_epe(v_model, truths):.3f}  "
          f"speed {speed_ratio(v_model, truths):.2f}")
    print(f"reference V           rel. EPE {rel_epe(v_ref, truths):.3f}  "
          f"speed {ref_speed:.2f}")
    print(f"reference x {to_model:.2f} (the model's speed)  rel. EPE "
          f"{rel_epe(v_ref, truths, to_model):.3f}")
    print(f"reference x {best:.2f} (best scale)  rel. EPE "
          f"{rel_epe(v_ref, truths, best):.3f}")


if __name__ == "__main__":
    main()
