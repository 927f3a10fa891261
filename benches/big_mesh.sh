#!/bin/sh
# How time and memory grow with a mesh's size: a bumpy torus of N
# triangles (examples/torus_ply.rs, binary PLY) over a floor, one Point
# light, 512 x 512, the whole process; prints seconds and peak RSS per
# size and the fitted exponent of time = c n^e. Not run in CI.
# With SHAPE=sheet the mesh is an open wavy sheet of N triangles instead
# (examples/sheet_ply.rs, `type concave`: it may shadow itself), alone.
# With POVRAY=1 (and povray on the PATH), POV-Ray 3.7 renders the same
# triangles (examples/to_pov; +A0.0 +AM1 +R3, as benches/side_by_side.sh)
# after each size, and its time and peak are printed beside ours.
#
#   [POVRAY=1] [SHAPE=sheet] benches/big_mesh.sh [N...]
#   (default 100000 1000000 10000000)
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
cargo build --release --quiet --manifest-path "$root/Cargo.toml" --bin plytrace --example torus_ply --example sheet_ply \
    --example to_pov
bin="$root/target/release"
work=$(mktemp -d /tmp/plytrace-big.XXXXXX)
trap 'rm -rf "$work"' EXIT
mkdir "$work/det"
cat >"$work/det/floor.det" <<'DET'
title floor
data
4 1
-3 -3 -0.6
3 -3 -0.6
3 3 -0.6
-3 3 -0.6
4 4 3 2 1
DET
cat >"$work/mesh.des" <<'DES'
resolution 512 512
perspective 40 1 0.1 100
light 3 -4 6 1 1 1 100 Point
pushmatrix
ident
polarview 4 25 55 0
color 0.8 0.7 0.5
DES
if [ "${SHAPE:-torus}" = sheet ]; then
    printf 'type concave\ndefobj mesh\nendobj\npopmatrix\n' >>"$work/mesh.des"
else
    printf 'defobj mesh\nendobj\ncolor 0.6 0.6 0.7\ndefobj floor\nendobj\npopmatrix\n' >>"$work/mesh.des"
fi
cd "$work"
for n in ${*:-100000 1000000 10000000}; do
    "$bin/examples/${SHAPE:-torus}_ply" "$n" det/mesh.ply
    /usr/bin/time -f "$n %e %M" "$bin/plytrace" mesh.des -q --max-polygons 100000000 \
        --max-tree-nodes 1000000000 -o mesh.png 2>>times.txt
    tail -n 1 times.txt | awk '{ printf "%12d triangles  %7.2f s  %6.0f MB peak\n", $1, $2, $3 / 1024 }'
    if [ "${POVRAY:-0}" = 1 ]; then
        "$bin/examples/to_pov" mesh.des 512 mesh.pov 2>/dev/null
        /usr/bin/time -f "%e %M" povray +Imesh.pov +Omesh-pov.png +W512 +H512 +A0.0 +AM1 +R3 -D \
            2>&1 >/dev/null | tail -n 1 |
            awk '{ printf "%12s  POV-Ray  %7.2f s  %6.0f MB peak\n", "", $1, $2 / 1024 }'
        rm -f mesh.pov
    fi
done
awk 'NF == 3 { x = log($1); y = log($2); n++; sx += x; sy += y; sxx += x * x; sxy += x * y }
     END { if (n > 1) printf "time ~ n^%.2f\n", (n * sxy - sx * sy) / (n * sxx - sx * sx) }' times.txt
