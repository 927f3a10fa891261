#!/bin/sh
# A camera walking through a still scene: 120 frames (`run y`, both
# shadow kinds, mirrors) at the scene's resolution, one process, frames
# written as PNG. The camera turns from -10 to +10 degrees and moves
# forward 0.03 units a frame; only the projection changes, so every frame
# after the first reuses the shadows cast on whole polygons. Prints the
# frames per second from the first frame to the last (the whole process).
# Not run in CI.
#
#   benches/walkthrough.sh [SCENE...]   (default office2 gallery)
#   PLYTRACE=/path/to/plytrace benches/walkthrough.sh   (another build)
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
if [ -z "${PLYTRACE:-}" ]; then
    cargo build --release --quiet --manifest-path "$root/Cargo.toml" --bin plytrace
fi
bin="${PLYTRACE:-$root/target/release/plytrace}"
work=$(mktemp -d /tmp/plytrace-walk.XXXXXX)
trap 'rm -rf "$work"' EXIT
cp -r "$root/tests/data/scenes/det" "$work/det"
frames=120
for scene in ${*:-office2 gallery}; do
    src="$root/tests/data/scenes/$scene.des"
    fov=$(awk '$1 == "perspective" { print $2; exit }' "$src")
    {
        cat "$src"
        awk -v n=$frames -v fov="$fov" 'BEGIN {
            for (k = 0; k < n; k++)
                printf "ident\nperspective %s 1.0 0.01 1000.0\nrotate %.4f y\ntranslate 0 0 %.4f\nfname f%03d\nrun y\n",
                    fov, -10 + 20 * k / n, 0.03 * k, k
        }'
    } >"$work/walk.des"
    start=$(date +%s.%N)
    (cd "$work" && "$bin" -q walk.des)
    end=$(date +%s.%N)
    awk -v s="$start" -v e="$end" -v n=$frames -v name="$scene" \
        'BEGIN { printf "%-10s %d frames  %6.2f s  %5.1f frames/s\n", name, n, e - s, n / (e - s) }'
    rm -f "$work"/f*.png
done
