#!/usr/bin/env bash
# Recovers camera poses for a scene's frames with COLMAP (feature extraction
# with one shared camera, sequential matching for video, incremental mapping)
# and writes the model as text.
#
#   scripts/colmap_poses.sh SCENE_DIR [OUT_DIR]
#
# Reads SCENE_DIR/images. Writes OUT_DIR (default SCENE_DIR/sparse/0). If the
# default output already exists (e.g. a synthetic scene's exact poses), an
# explicit OUT_DIR is required so ground truth is never overwritten.
# Environment: CAMERA_MODEL (PINHOLE or SIMPLE_RADIAL, default PINHOLE),
# MATCHER (sequential or exhaustive, default sequential), COLMAP (binary).
set -euo pipefail

if [[ "${1:-}" == -h || "${1:-}" == --help ]]; then
  sed -n '2,12p' "$0"
  exit 0
fi
if [[ $# -lt 1 || $# -gt 2 ]]; then
  echo "usage: $0 SCENE_DIR [OUT_DIR]" >&2
  exit 2
fi
scene=$(realpath "$1")
images="$scene/images"
out=${2:-$scene/sparse/0}
colmap=${COLMAP:-colmap}
camera_model=${CAMERA_MODEL:-PINHOLE}
matcher=${MATCHER:-sequential}

[[ -d "$images" ]] || { echo "error: $images: no such directory" >&2; exit 1; }
if [[ $# -eq 1 && -e "$out" ]]; then
  echo "error: $out exists; give an output directory as the 2nd argument" >&2
  exit 1
fi
case "$camera_model" in PINHOLE|SIMPLE_RADIAL) ;; *)
  echo "error: CAMERA_MODEL must be PINHOLE or SIMPLE_RADIAL" >&2; exit 1;;
esac
case "$matcher" in sequential|exhaustive) ;; *)
  echo "error: MATCHER must be sequential or exhaustive" >&2; exit 1;;
esac
command -v "$colmap" > /dev/null || { echo "error: $colmap not found" >&2; exit 1; }

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
db="$work/database.db"
start=$(date +%s)

# COLMAP's Qt GUI parts need no display when told so.
export QT_QPA_PLATFORM=offscreen

# Progress: the step (k/4) and the time so far; COLMAP's own logs go to
# files that are shown only when a step fails.
step() {
  echo "[colmap $1/4] $2 ($(( $(date +%s) - start )) s so far)"
}
num_images=$(find "$images" -maxdepth 1 -type f \( -iname '*.png' \
  -o -iname '*.jpg' -o -iname '*.jpeg' \) | wc -l)

step 1 "feature extraction, $num_images images"
"$colmap" feature_extractor --database_path "$db" --image_path "$images" \
  --ImageReader.single_camera 1 --ImageReader.camera_model "$camera_model" \
  --SiftExtraction.use_gpu 0 > "$work/extract.log" 2>&1 \
  || { tail -20 "$work/extract.log" >&2; exit 1; }

step 2 "$matcher matching"
if [[ "$matcher" == sequential ]]; then
  # Loop detection needs a vocabulary tree; video overlap is enough here.
  "$colmap" sequential_matcher --database_path "$db" \
    --SiftMatching.use_gpu 0 --SequentialMatching.overlap 10 \
    > "$work/match.log" 2>&1 || { tail -20 "$work/match.log" >&2; exit 1; }
else
  "$colmap" exhaustive_matcher --database_path "$db" \
    --SiftMatching.use_gpu 0 > "$work/match.log" 2>&1 \
    || { tail -20 "$work/match.log" >&2; exit 1; }
fi

step 3 "incremental mapping"
mkdir -p "$work/sparse"
"$colmap" mapper --database_path "$db" --image_path "$images" \
  --output_path "$work/sparse" > "$work/map.log" 2>&1 \
  || { tail -20 "$work/map.log" >&2; exit 1; }

step 4 "choosing the largest model, writing text"
# The mapper may split the video into several models; keep the largest.
best="" best_count=-1
for model in "$work"/sparse/*/; do
  [[ -f "$model/images.bin" ]] || continue
  "$colmap" model_converter --input_path "$model" --output_path "$model" \
    --output_type TXT > /dev/null 2>&1
  # Pose lines have 10 fields; 2D point lines a multiple of 3.
  count=$(grep -v '^#' "$model/images.txt" | awk 'NF == 10' | wc -l)
  if (( count > best_count )); then best=$model; best_count=$count; fi
done
[[ -n "$best" ]] || { echo "error: COLMAP registered no images" >&2; exit 1; }

mkdir -p "$out"
cp "$best"/cameras.txt "$best"/images.txt "$best"/points3D.txt "$out"/
total=$(find "$images" -maxdepth 1 -type f \( -iname '*.png' -o -iname '*.jpg' \
  -o -iname '*.jpeg' \) | wc -l)
models=$(find "$work/sparse" -mindepth 1 -maxdepth 1 -type d | wc -l)
echo "registered $best_count of $total frames (largest of $models models)" \
  "in $(( $(date +%s) - start )) s -> $out"
