#!/bin/sh
# Walkthroughs along several camera paths, with the scene's own camera:
# each frame is `pushmatrix`, the path's move, `run y`, `popmatrix`
# after the scene file, so the move acts on the scene's eye space (the
# eye at the origin, looking down -z, y up) as a user's script would.
# 120 frames a path at the scene's resolution (512 x 512), one process,
# every frame written as a PNG. The paths:
#
#   turn   the camera turns from -20 to +20 degrees (`rotate A y`)
#   walk   it walks 2.4 units straight ahead (`translate 0 0 Z`)
#   look   it looks from 15 degrees down to 15 up (`rotate B x`)
#   roll   it rolls from -10 to +10 degrees (`rotate C z`)
#   stroll it turns from -12 to +12 degrees while it walks 0.6 ahead
#
# Prints, per scene and path, the frames per second of the whole process
# (median of RUNS runs, and the slowest and fastest), the median CPU
# seconds (user + system) and peak memory. Not run in CI.
#
#   benches/walk_paths.sh [SCENE...]          (default office2 gallery)
#   PATHS="turn walk" RUNS=3 FRAMES=60 benches/walk_paths.sh office2
#   PLYTRACE=/path/to/plytrace benches/walk_paths.sh   (another build)
#   CHECK=1 ...      also render every frame cold (`--frames K`, its own
#                    process) and compare the PNGs byte for byte
#   CALLGRIND=1 ...  also count instructions per frame under callgrind
#                    (one run; slow: about 5 minutes a path of office2)
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
if [ -z "${PLYTRACE:-}" ]; then
    cargo build --release --quiet --manifest-path "$root/Cargo.toml" --bin plytrace
fi
bin="${PLYTRACE:-$root/target/release/plytrace}"
frames=${FRAMES:-120}
runs=${RUNS:-5}
work=$(mktemp -d /tmp/plytrace-paths.XXXXXX)
trap 'rm -rf "$work"' EXIT
cp -r "$root/tests/data/scenes/det" "$work/det"

# The move of frame k of path $1 (s runs from 0 to 1 along the path).
moves() {
    awk -v n="$frames" -v path="$1" 'BEGIN {
        for (k = 0; k < n; k++) {
            s = n > 1 ? k / (n - 1) : 0
            if (path == "turn") m = sprintf("rotate %.4f y", -20 + 40 * s)
            else if (path == "walk") m = sprintf("translate 0 0 %.4f", 2.4 * s)
            else if (path == "look") m = sprintf("rotate %.4f x", -15 + 30 * s)
            else if (path == "roll") m = sprintf("rotate %.4f z", -10 + 20 * s)
            else if (path == "stroll") m = sprintf("rotate %.4f y\ntranslate 0 0 %.4f", -12 + 24 * s, 0.6 * s)
            else { print "unknown path " path > "/dev/stderr"; exit 2 }
            printf "pushmatrix\n%s\nfname f%03d\nrun y\npopmatrix\n", m, k
        }
    }'
}

# Seconds of wall and CPU time and peak KiB of one run of walk.des.
timed() {
    if [ -x /usr/bin/time ]; then
        /usr/bin/time -f "%e %U %S %M" -o "$work/time.txt" "$bin" -q walk.des
        awk '{ printf "%s %.3f %s\n", $1, $2 + $3, $4 }' "$work/time.txt"
    else
        start=$(date +%s.%N)
        "$bin" -q walk.des
        end=$(date +%s.%N)
        awk -v s="$start" -v e="$end" 'BEGIN { printf "%.3f 0 0\n", e - s }'
    fi
}

# Every frame against its cold render: the same file, only frame k.
check() {
    mkdir -p cold
    bad=0
    k=0
    while [ "$k" -lt "$frames" ]; do
        name=$(printf "f%03d.png" "$k")
        (cd cold && "$bin" -q --frames "$k" ../walk.des)
        cmp -s "$name" "cold/$name" || { echo "  frame $k differs from its cold render"; bad=1; }
        rm -f "cold/$name"
        k=$((k + 1))
    done
    [ "$bad" = 0 ] && echo "  every frame equals its cold render (byte-identical PNG)"
    return "$bad"
}

status=0
cd "$work"
for scene in ${*:-office2 gallery}; do
    for path in ${PATHS:-turn walk look roll stroll}; do
        { cat "$root/tests/data/scenes/$scene.des"; moves "$path"; } >walk.des
        : >runs.txt
        r=0
        while [ "$r" -lt "$runs" ]; do
            timed >>runs.txt
            r=$((r + 1))
        done
        sort -n runs.txt | awk -v n="$frames" -v name="$scene" -v path="$path" '
            { wall[NR] = $1; cpu[NR] = $2; mem[NR] = $3 }
            END {
                m = int((NR + 1) / 2)
                for (i = 1; i <= NR; i++) c[i] = cpu[i]
                for (i = 1; i <= NR; i++) for (j = i + 1; j <= NR; j++) if (c[j] < c[i]) { t = c[i]; c[i] = c[j]; c[j] = t }
                printf "%-8s %-6s %d frames  %6.1f frames/s (%.1f-%.1f, %d runs)  %6.2f s  CPU %6.2f s  %4.0f MiB\n",
                    name, path, n, n / wall[m], n / wall[NR], n / wall[1], NR, wall[m], c[m], mem[m] / 1024
            }'
        if [ "${CALLGRIND:-0}" = 1 ]; then
            valgrind --tool=callgrind --callgrind-out-file=cg.out "$bin" -q walk.des 2>cg.txt
            awk -v n="$frames" '/Collected :/ { printf "         %-6s %.1f M instructions a frame\n", "", $NF / n / 1e6 }' cg.txt
            rm -f cg.out*
        fi
        if [ "${CHECK:-0}" = 1 ]; then
            check || status=1
        fi
        rm -f f*.png
    done
done
exit "$status"
