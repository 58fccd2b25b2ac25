#!/usr/bin/env bash
# The main job: installs what is missing, builds, builds the default HRIR
# database and the samples' head mesh into out/, and renders the samples
# into out/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh build
mkdir -p out
db=out/satf-default.hrirdb.exr
if build/bin/satf-db verify "$db" >/dev/null 2>&1; then
  echo "main: $db is present and intact (delete it to rebuild)"
else
  build/bin/satf-build -o "$db"
fi
build/bin/satf-db info "$db"
# the physically based records of the fibre model (--shading physical)
fdb=out/satf-fiber.hrirdb.exr
if build/bin/satf-db verify "$fdb" >/dev/null 2>&1; then
  echo "main: $fdb is present and intact (delete it to rebuild)"
else
  build/bin/satf-build --kind fiber -o "$fdb"
fi
# the head the hairstyle samples sit on (their "meshes": ../out/head.obj)
python3 scripts/gen-head.py out/head.obj
if [ -x build/bin/satf-render ]; then
  bash scripts/render-samples.sh build "$db" out "$fdb"
fi
