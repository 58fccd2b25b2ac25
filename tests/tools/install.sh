#!/bin/sh
# The installed tools work from their prefix: `satf-build --install-default`
# writes both default databases into the data folder (tiny ones here), then
# `cmake --install BUILD --prefix P` puts the programs in P/bin, and the
# installed satf-render renders a scene that names no database (the build's
# own satf-render, which looks in its own prefix, refuses it), takes the
# fibre database beside the default for physical shading.
# usage: install.sh BUILD_DIR SOURCE_DIR WORK_DIR
set -eu
build=$1 src=$2 d=$3
rm -rf "$d"
mkdir -p "$d"
p=$d/prefix
tiny="--samples 12 --angles 12x12 --width 8 --grid 8 --sub-rays 2 -q"
# shellcheck disable=SC2086
SATF_DATA_DIR=$p/share/satf "$build/bin/satf-build" --install-default $tiny
test -s "$p/share/satf/satf-default.hrirdb.exr"
test -s "$p/share/satf/satf-fiber.hrirdb.exr"
"$build/bin/satf-db" info "$p/share/satf/satf-fiber.hrirdb.exr" |
  grep -q 'fiber records'
cmake --install "$build" --prefix "$p" > "$d/install.log"
for t in satf-build satf-db satf-render satf-view satf-import satf-compare; do
  test -x "$p/bin/$t"
done
sed '/"database"/d' "$src/samples/cluster_6c.json" > "$d/nodb.json"
! grep -q database "$d/nodb.json"
env -u SATF_DATA_DIR "$p/bin/satf-render" "$d/nodb.json" --size 96x72 -q \
  -o "$d/kk.exr"
test -s "$d/kk.exr"
env -u SATF_DATA_DIR "$p/bin/satf-render" "$d/nodb.json" --size 96x72 \
  --shading physical -o "$d/phys.exr" 2> "$d/phys.err"
test -s "$d/phys.exr"
grep -q "takes the fibre database $p/share/satf/satf-fiber" "$d/phys.err"
if env -u SATF_DATA_DIR "$build/bin/satf-render" "$d/nodb.json" --size 96x72 \
  -q -o "$d/no.exr" 2> "$d/no.err"; then
  exit 1
fi
grep -q 'no database: give --db DB.exr' "$d/no.err"
grep -q 'satf-build --install-default' "$d/no.err"
