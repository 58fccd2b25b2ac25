#!/bin/sh
# Ctrl-C during --frames: satf-render finishes the frame it is on, says how
# many of the range are finished and that --resume continues, and exits
# 130; --resume then renders only the rest.
# usage: frames_interrupted.sh SATF_RENDER SCENE DB WORK_DIR
set -eu
render=$1 scene=$2 db=$3 d=$4
rm -rf "$d"
mkdir -p "$d"
"$render" "$scene" --db "$db" --frames 1-48 --size 96x72 \
  -o "$d/f_%04d.exr" > "$d/out" 2> "$d/err" &
pid=$!
n=0
while [ ! -e "$d/f_0002.exr" ] && [ $n -lt 600 ]; do
  sleep 0.1
  n=$((n + 1))
done
kill -INT $pid
rc=0
wait $pid || rc=$?
cat "$d/err"
test $rc -eq 130
grep -q 'interrupted: frames 1-48: [0-9]* of 48 finished' "$d/err"
grep -q 'the same command with --resume continues' "$d/err"
done=$(ls "$d" | grep -c '^f_.*\.exr$')
test "$done" -lt 48
"$render" "$scene" --db "$db" --frames 1-48 --size 96x72 \
  -o "$d/f_%04d.exr" --resume > "$d/out2"
grep -q "$((48 - done)) rendered, $done already complete" "$d/out2"
