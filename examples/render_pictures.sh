#!/bin/sh
# The README's render pictures: for one volume, side by side, the source by the
# anti-aliased ray marcher (the reference), dense shear-warp of the source,
# Gaussian shear-warp of a fitted asset, and where the Gaussian image differs from
# the reference (gvr eval --difference, errors x 4).
#
#   examples/render_pictures.sh SOURCE.vdb ASSET.gvr TF OUT.png [SIZE]
#
# e.g. examples/render_pictures.sh out/ct-head.vdb out/ct-head.gvr mri docs/images/render-ct-head.png
# (examples/tf-surface.json is bench_render's surface classification, for data of 0 to 255)
# Needs gvr in build/cli (or GVR set) and oiiotool (openimageio-tools).
set -eu
source=$1 asset=$2 tf=$3 out=$4 size=${5:-320x320}
gvr=${GVR:-build/cli/gvr}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
view="--azimuth 30 --elevation 15 --tf $tf --size $size -q"
"$gvr" render "$source" -o "$work/reference.exr" $view --renderer raymarch --samples 4
"$gvr" render "$source" -o "$work/dense.exr" $view
"$gvr" render "$asset" -o "$work/gaussians.exr" $view
"$gvr" eval "$work/reference.exr" "$work/gaussians.exr" --difference "$work/difference.exr" > /dev/null
# Over black, as the difference image is (premultiplied RGB is the image over black),
# with the values gvr render writes to PNG.
oiiotool "$work/reference.exr" "$work/dense.exr" "$work/gaussians.exr" "$work/difference.exr" \
    --mosaic:pad=4 4x1 --ch R,G,B -d uint8 -o "$out"
echo "wrote $out"
