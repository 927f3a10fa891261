#!/bin/sh
# Runs the fuzz targets one after the other, each for SECONDS (default 600),
# at the lowest priority, on stable (no sanitizer); logs to LOGDIR.
# Usage: fuzz/run-all.sh [SECONDS] [TARGET...]
set -u
cd "$(dirname "$0")"
secs=${1:-600}
[ $# -gt 0 ] && shift
targets=${*:-"scene_language object_files meshes tree_files pipeline pixel_structs rftb_args patch_files modeling"}
logdir=${LOGDIR:-/tmp}
for t in $targets; do
    mkdir -p "corpus/$t" "artifacts/$t"
    dict=""
    [ -f "$t.dict" ] && dict="-dict=$t.dict"
    nice -n 19 cargo fuzz run "$t" --sanitizer none --target x86_64-unknown-linux-gnu \
        "corpus/$t" "../tests/data/fuzz-regressions/$t" -- \
        -max_total_time="$secs" -timeout=10 -rss_limit_mb=2048 -max_len=4096 \
        -fork=1 -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1 \
        -print_final_stats=1 $dict >"$logdir/fuzz-$t.log" 2>&1
    echo "$t exit $?" >>"$logdir/fuzz-summary.log"
done
