#!/usr/bin/env bash
# Recovers camera poses for a scene's frames with COLMAP, with settings for
# video (one shared camera, capped features, sequential matching, SfM at a
# reduced width): a wrapper around es_poses, which prints registered / total
# frames and the mean reprojection error and writes pose_report.json.
#
#   scripts/colmap_poses.sh SCENE_DIR [OUT_DIR]
#
# Reads SCENE_DIR/images. Writes OUT_DIR (default SCENE_DIR/sparse/0), which
# must not exist, so ground truth is never overwritten. Environment:
# CAMERA_MODEL (SIMPLE_PINHOLE, PINHOLE or SIMPLE_RADIAL), COLMAP (binary), ES_BIN (where
# es_poses is, default build/bin), ES_POSE_FLAGS (more es_poses flags).
set -euo pipefail

if [[ "${1:-}" == -h || "${1:-}" == --help ]]; then
  sed -n '2,12p' "$0"
  exit 0
fi
if [[ $# -lt 1 || $# -gt 2 ]]; then
  echo "usage: $0 SCENE_DIR [OUT_DIR]" >&2
  exit 2
fi
root=$(cd "$(dirname "$0")/.." && pwd)
bin=${ES_BIN:-$root/build/bin}
out=${2:-$1/sparse/0}
# shellcheck disable=SC2086
exec "$bin/es_poses" --scene "$1" --out "$out" \
  --camera_model "${CAMERA_MODEL:-SIMPLE_PINHOLE}" --colmap "${COLMAP:-colmap}" \
  ${ES_POSE_FLAGS:-}
