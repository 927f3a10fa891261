#!/bin/sh
# Whole-process wall time of plytrace and POV-Ray 3.7 on the same
# geometry, in one run (POV-Ray with +A0.0 +AM1 +R3), at
# 512 x 512: office2 with its 2 shadow lights, office2 without shadows
# (`run` without `y`), gallery with its 4. Median of RUNS runs (default 5).
# Needs `cargo build --release --example to_pov` and `povray` on the PATH.
# Usage: benches/side_by_side.sh [RUNS]
set -eu
RUNS=${1:-5}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
TARGET=${CARGO_TARGET_DIR:-$ROOT/target}
PLY=$TARGET/release/plytrace
TOPOV=$TARGET/release/examples/to_pov
for tool in "$PLY" "$TOPOV"; do
    if [ ! -x "$tool" ]; then
        echo "side_by_side.sh: $tool is missing; build it first:" >&2
        echo "    cargo build --release --bin plytrace --example to_pov" >&2
        exit 2
    fi
done
if [ ! -x /usr/bin/time ]; then
    echo "side_by_side.sh: /usr/bin/time is needed (Debian: apt-get install time)" >&2
    exit 2
fi
if ! command -v povray >/dev/null; then
    echo "side_by_side.sh: povray is not on the PATH; its column is left empty" >&2
fi
SCENES=$ROOT/tests/data/scenes
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
ln -s "$SCENES/det" "$WORK/det"
cp "$SCENES/office2.des" "$SCENES/gallery.des" "$WORK/"
{ cat "$SCENES/office2.des"; echo run; } > "$WORK/office2-no-shadows.des"
cd "$WORK"
median() { sort -n | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
wall() { /usr/bin/time -f %e "$@" 2>&1 >/dev/null | tail -1; }
printf '%-20s %12s %12s %8s\n' scene plytrace_s povray_s ratio
for s in office2 office2-no-shadows gallery; do
    "$TOPOV" "$s.des" 512 "$s.pov" 2>/dev/null
    p=$(for i in $(seq "$RUNS"); do wall "$PLY" -i -f "$s.des" -o "$s.png" --size 512x512; done | median)
    if command -v povray >/dev/null; then
        [ "$s" = office2-no-shadows ] && sed -i 's/^light_source {\(.*\) }$/light_source {\1 shadowless }/' "$s.pov"
        v=$(for i in $(seq "$RUNS"); do wall povray "+I$s.pov" "+O$s-pov.png" +W512 +H512 +A0.0 +AM1 +R3 -D; done | median)
        r=$(awk -v a="$v" -v b="$p" 'BEGIN {printf "%.1f", a / b}')
    else
        v=-; r=-
    fi
    printf '%-20s %12s %12s %8s\n' "$s" "$p" "$v" "$r"
done
