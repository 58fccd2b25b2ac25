#!/bin/bash
# The hostile-input corpus: damaged databases, hostile strand files of each
# format, hostile scenes, command-line abuse, a kill -9 during a build and
# outputs on a read-only directory. Inputs are generated here, small; every
# run is under a memory limit (ulimit -v) and a time limit, so a runaway or
# a hang fails its case instead of taking the machine. A case passes when
# the tool ends by itself (no signal, no timeout) with the expected status
# and, for refusals, a message.
# Usage: hostile.sh BIN_DIR SOURCE_DIR WORK_DIR
set -u
bin=$1 src=$2 d=$3
rm -rf "$d"
mkdir -p "$d"
cd "$d" || exit 1
ulimit -v 4000000
fails=0 cases=0

# expect refuse|ok SECONDS NAME -- COMMAND...: refuse wants status 1-123
# and some stderr, ok wants status 0.
expect() {
  local want=$1 limit=$2 name=$3
  shift 4
  cases=$((cases + 1))
  timeout -s KILL "$limit" "$@" >"$name.out" 2>"$name.err" </dev/null
  local rc=$?
  local bad=
  if [ "$want" = ok ]; then
    [ $rc -eq 0 ] || bad="status $rc"
  elif [ $rc -eq 0 ]; then
    bad="accepted"
  elif [ $rc -ge 124 ]; then
    bad="status $rc (signal, timeout or memory limit)"
  elif [ ! -s "$name.err" ]; then
    bad="refused without a message"
  fi
  if [ -n "$bad" ]; then
    echo "FAIL $name: $bad"
    tail -3 "$name.err"
    fails=$((fails + 1))
  fi
}

B=$bin
"$B/satf-build" -q --samples 16 --angles 8 --width 16 --grid 8 -o db.exr ||
  exit 1
size=$(stat -c %s db.exr)

# ---- damaged databases
head -c $((size / 2)) db.exr >db_half.exr
head -c 100 db.exr >db_head.exr
: >db_empty.exr
cp db.exr db_flip.exr
printf '\377\377\377\377' | dd of=db_flip.exr bs=1 seek=$((size / 3)) \
  conv=notrunc 2>/dev/null
for f in db_half db_head db_empty db_flip; do
  expect refuse 20 "verify_$f" -- "$B/satf-db" verify "$f.exr"
  expect refuse 30 "render_$f" -- "$B/satf-render" \
    "$src/samples/cluster_6a.json" --db "$f.exr" --size 32x24 -o x.exr -q
done
# damage a reader gets past with the pixels intact, which verify must still
# find: bytes after the last chunk, a zeroed offset table, another line order
python3 - <<'PY'
import struct
data = open('db.exr', 'rb').read()
open('db_tail.exr', 'wb').write(data + bytes(range(256)) * 3)
at = 8  # magic and version, then attributes until an empty name
order = None
while data[at] != 0:
    name_end = data.index(b'\0', at)
    type_end = data.index(b'\0', name_end + 1)
    size, = struct.unpack_from('<i', data, type_end + 1)
    if data[at:name_end] == b'lineOrder':
        order = type_end + 5
    at = type_end + 5 + size
table = at + 1
b = bytearray(data)
b[table:table + 64] = bytes(64)
open('db_table.exr', 'wb').write(b)
b = bytearray(data)
b[order] = 1
open('db_order.exr', 'wb').write(b)
PY
for f in db_tail db_table db_order; do
  expect refuse 20 "verify_$f" -- "$B/satf-db" verify "$f.exr"
done
mkfifo db_fifo.exr
expect refuse 10 verify_db_fifo -- "$B/satf-db" verify db_fifo.exr

# ---- hostile strand files
# .hair: a header claiming 4G strands, a truncated body, garbage
printf 'HAIR\377\377\377\377\377\377\377\377\003\000\000\000' >huge.hair
head -c 112 /dev/zero >>huge.hair
printf 'HAIR\004\000\000\000\010\000\000\000\003\000\000\000' >cut.hair
head -c 120 /dev/zero >>cut.hair
head -c 4096 /dev/urandom >noise.hair
# .tfx: garbage and a header with absurd counts
head -c 4096 /dev/urandom >noise.tfx
printf '\377\377\377\177\377\377\377\177' >counts.tfx
head -c 200 /dev/zero >>counts.tfx
# .ply: a header whose counts exceed the body, and a binary one cut short
printf 'ply\nformat ascii 1.0\nelement vertex 2000000000\nproperty float x\nproperty float y\nproperty float z\nelement strand 1\nproperty int n\nend_header\n0 0 0\n' >lies.ply
printf 'ply\nformat binary_little_endian 1.0\nelement vertex 100\nproperty float x\nproperty float y\nproperty float z\nend_header\n' >cut.ply
head -c 20 /dev/zero >>cut.ply
head -c 4096 /dev/urandom >noise.data
# .hair with one coordinate of 1e30 (within a float, past any unit)
python3 -c "
import struct, sys
pts = [0, 0, 0, 0, -1, 0, 1e30, 0, 0, 1, -1, 0]
sys.stdout.buffer.write(b'HAIR' + struct.pack('<IIIIfffff', 2, 4, 2, 1, 0.01, 0, 0, 0, 0) + bytes(88) + struct.pack('<12f', *pts))
" >far.hair
mkfifo fifo.hair
for f in huge.hair cut.hair noise.hair noise.tfx counts.tfx lies.ply cut.ply \
  noise.data fifo.hair /dev/zero far.hair; do
  n=import_$(basename "$f" | tr . _)
  expect refuse 30 "$n" -- "$B/satf-import" "$f" -o "$n.json" -q
done
grep -q "strand 1 point 0 has the coordinate 1e+30" import_far_hair.err ||
  { echo "FAIL import_far_hair: the refusal does not name the point"; fails=$((fails + 1)); }

# imports whose work would be absurd are refused before it starts, naming
# the flag: 200K two-point strands over a low budget, TressFX followers
# over the budget and over TressFX's limit
python3 -c "
import struct, sys
from array import array
n = 200000
p = array('f', [0.0]) * (6 * n)
for i in range(n):
    p[6 * i] = p[6 * i + 3] = (i % 500) * 0.01
    p[6 * i + 2] = p[6 * i + 5] = (i // 500) * 0.01
    p[6 * i + 4] = -1.0
sys.stdout.buffer.write(b'HAIR' + struct.pack('<IIIIfffff', n, 2 * n, 2, 1, 0.01, 0, 0, 0, 0) + bytes(88) + p.tobytes())
" >short.hair
expect refuse 30 import_short_budget -- "$B/satf-import" short.hair -o s.json \
  -q --memory-budget 0.02
grep -q -- "--memory-budget" import_short_budget.err ||
  { echo "FAIL import_short_budget: the refusal does not name the flag"; fails=$((fails + 1)); }
python3 -c "
import struct, sys
from array import array
g, v = 2000, 16
h = bytearray(296)
struct.pack_into('<fIIII', h, 0, 3.0, g, v, 128, 0)
p = array('f', [0.0]) * (3 * g * v)
for i in range(g):
    for k in range(v):
        p[3 * (i * v + k)] = (i % 50) * 0.1
        p[3 * (i * v + k) + 1] = -0.2 * k
        p[3 * (i * v + k) + 2] = (i // 50) * 0.1
sys.stdout.buffer.write(bytes(h) + p.tobytes())
" >follow.tfx
expect refuse 30 import_follow_budget -- "$B/satf-import" follow.tfx -o f.json \
  -q --memory-budget 0.05
grep -q -- "--follow" import_follow_budget.err ||
  { echo "FAIL import_follow_budget: the refusal does not name --follow"; fails=$((fails + 1)); }
expect refuse 10 import_follow_limit -- "$B/satf-import" follow.tfx -o f.json \
  -q --follow 5000

# 20K two-point strands split into 8192 clusters: each macro-cluster held
# room for every cluster's instance (1.3 GB); within 1 GB of address space
python3 -c "
import math, struct, sys
from array import array
n, side = 20000, 142
p = array('f')
for i in range(n):
    x, z = (i % side) * 0.01, (i // side) * 0.01
    for k in range(2):
        p.extend((x + 0.002 * math.sin(k + i), -k * 0.05, z + 0.002 * math.cos(k * 0.7 + i)))
sys.stdout.buffer.write(b'HAIR' + struct.pack('<IIIIfffff', n, 2 * n, 2, 1, 0.01, 0, 0, 0, 0) + bytes(88) + p.tobytes())
" >clusters.hair
expect ok 120 import_many_clusters -- bash -c 'ulimit -v 1000000; exec "$@"' \
  _ "$B/satf-import" clusters.hair -o c.json -q

# ---- hostile scenes
scene() { # NAME DENSITY-JSON [image]
  printf '{"macro_clusters": [{"prototype": {"trajectory": [[0,-3,0],[0,3,0]], "a": 1, "b": 1, "shell": {"layers": 2, "st": 4, "su": 8}, "density": %s}}], "camera": {"position": [0,0,30], "target": [0,0,0], "fov_y": 0.8}, "lights": [{"direction": [0,0,-1]}], "image": {"width": 32, "height": 24}}\n' "$2" >"$1.json"
}
mkfifo density.vdb
scene fifo_density '{"type": "vdb", "file": "density.vdb"}'
expect refuse 20 scene_fifo_density -- "$B/satf-render" fifo_density.json \
  --db db.exr -o x.exr -q
scene dev_density '{"type": "vdb", "file": "/dev/zero"}'
expect refuse 20 scene_dev_density -- "$B/satf-render" dev_density.json \
  --db db.exr -o x.exr -q
scene many_strands '{"strands": 10000000, "strand_width": 0.01}'
expect refuse 20 scene_many_strands -- "$B/satf-render" many_strands.json \
  --db db.exr -o x.exr -q --memory-budget 0.3
grep -q "the most is strands" scene_many_strands.err ||
  { echo "FAIL scene_many_strands: the refusal does not name the strands"; fails=$((fails + 1)); }
# 10M procedural strands within a 1 GB budget: set up in bounded time (the
# density queries scanned every strand within 0.1 of each: minutes)
expect ok 90 scene_many_strands_budget -- "$B/satf-render" many_strands.json \
  --db db.exr -o many.exr -q --memory-budget 1
scene huge_image '{"strands": 100, "strand_width": 0.05}'
expect refuse 20 scene_huge_image -- "$B/satf-render" huge_image.json \
  --db db.exr -o x.exr -q --size 16384x16384 --memory-budget 2
grep -q "the most is pixels" scene_huge_image.err ||
  { echo "FAIL scene_huge_image: the refusal does not name the pixels"; fails=$((fails + 1)); }
printf '{"macro_clusters": [' >deep.json
head -c 100000 /dev/zero | tr '\0' '[' >>deep.json
expect refuse 20 scene_deep -- "$B/satf-render" deep.json --db db.exr -o x.exr -q
head -c 100000 /dev/urandom >noise.json
expect refuse 20 scene_noise -- "$B/satf-render" noise.json --db db.exr -o x.exr -q
scene ok_scene '{"strands": 200, "strand_width": 0.05}'
expect ok 60 scene_ok -- "$B/satf-render" ok_scene.json --db db.exr -o ok.exr -q

# ---- command-line abuse
expect refuse 10 cli_size_zero -- "$B/satf-render" ok_scene.json --db db.exr --size 0x0 -o x.exr
expect refuse 10 cli_size_junk -- "$B/satf-render" ok_scene.json --db db.exr --size 12xx -o x.exr
expect refuse 10 cli_threads -- "$B/satf-render" ok_scene.json --db db.exr --threads -4 -o x.exr
expect refuse 10 cli_budget -- "$B/satf-render" ok_scene.json --db db.exr --memory-budget nan -o x.exr
expect refuse 10 cli_frames_static -- "$B/satf-render" ok_scene.json --db db.exr --frames 3-1 -o 'f_%04d.exr'
expect refuse 10 cli_output_dir -- "$B/satf-render" ok_scene.json --db db.exr -o /
expect refuse 10 cli_unknown -- "$B/satf-render" ok_scene.json --no-such-flag
expect refuse 10 cli_import_nothing -- "$B/satf-import"
expect refuse 10 cli_db_nothing -- "$B/satf-db" verify

# ---- kill -9 during a build: no file under the final name, and the next
# build writes a complete one
"$B/satf-build" -q --samples 400 --angles 16 --width 32 --grid 16 \
  -o killed.exr &
pid=$!
sleep 0.5
kill -9 $pid 2>/dev/null
wait $pid 2>/dev/null
cases=$((cases + 1))
if [ -e killed.exr ] && ! "$B/satf-db" verify killed.exr >/dev/null 2>&1; then
  echo "FAIL kill_build: a damaged killed.exr was left"
  fails=$((fails + 1))
fi
expect ok 60 rebuild_after_kill -- "$B/satf-build" -q --samples 16 --angles 8 \
  --width 16 --grid 8 -o killed.exr
ls | grep -q 'killed.exr.tmp' && { echo "FAIL kill_build: temp files stay"; fails=$((fails + 1)); }

# ---- a read-only directory (unless root, whom permissions do not stop)
mkdir ro
chmod 555 ro
if [ "$(id -u)" != 0 ]; then
  expect refuse 30 readonly_render -- "$B/satf-render" ok_scene.json \
    --db db.exr -o ro/x.exr -q
  expect refuse 30 readonly_build -- "$B/satf-build" -q --samples 16 \
    --angles 8 --width 16 --grid 8 -o ro/db.exr
fi
# a full disk
if [ -w /dev/full ]; then
  expect refuse 30 full_disk -- "$B/satf-render" ok_scene.json --db db.exr \
    -o /dev/full -q
fi
chmod 755 ro

echo "hostile corpus: $cases cases, $fails failed"
[ $fails -eq 0 ]
