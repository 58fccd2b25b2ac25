#!/usr/bin/env python3
"""scripts/check-layout.py on small made-up trees: a library whose files
call each other in a circle fails, through a call, a function's address
taken or a definition with its return type on a line of its own; files
calling one way pass, as does a file calling its own static function of
another file's function's name; the renderer's folder is held to the same
rule as every other.

usage: test_layout_circles.py CHECK_LAYOUT_PY"""
import os
import subprocess
import sys
import tempfile

CHECK = sys.argv[1]


def run(files):
    """check-layout's exit status and output on a tree of files."""
    with tempfile.TemporaryDirectory() as root:
        for rel, text in files.items():
            path = os.path.join(root, rel)
            os.makedirs(os.path.dirname(path), exist_ok=True)
            with open(path, 'w', encoding='utf-8') as f:
                f.write(text)
        p = subprocess.run([sys.executable, CHECK, root], capture_output=True,
                           text=True, check=False)
        return p.returncode, p.stdout


A_CALLS_B = '''/* a.c */
#include "satf/common.h"
int b_value(void);
int a_value(void) {
  return b_value() + 1; /* b_value() in a comment: not a call */
}
'''
B_CALLS_A = '''/* b.c */
int a_value(void);
int b_value(void) { return a_value() - 1; }
'''
B_ALONE = '''/* b.c: "a_value()" in a string is not a call */
static const char *name = "a_value()";
int b_value(void) { return name[0]; }
'''
B_TAKES_A = '''/* b.c */
int a_value(void);
typedef int (*fn)(void);
static const fn table[] = {a_value};
int b_value(void) { return table[0](); }
'''
A_SPLIT = '''int b_value(void);
int
a_value(void) {
  return b_value();
}
'''
B_STATIC_SPLIT = '''static int
a_value(void) { return 0; }
int b_value(void) { return a_value(); }
'''
C_CALLS_A = '''int a_value(void);
int c_value(void) { return a_value(); }
'''
failures = []


def expect(name, files, code, needle):
    rc, out = run(files)
    if rc != code or needle not in out:
        failures.append(f'{name}: exit {rc}, expected {code} with '
                        f'"{needle}":\n{out}')


expect('circle', {'db/a.c': A_CALLS_B, 'db/b.c': B_CALLS_A}, 1,
       'db: call circle a -> b -> a')
expect('address', {'db/a.c': A_CALLS_B, 'db/b.c': B_TAKES_A}, 1,
       'db: call circle a -> b -> a')
expect('split line', {'db/a.c': A_SPLIT, 'db/b.c': B_CALLS_A}, 1,
       'db: call circle a -> b -> a')
# b's own static a_value: no call into a.c
expect('static', {'db/a.c': A_SPLIT, 'db/b.c': B_STATIC_SPLIT}, 0,
       'layout: 0 violation')
expect('one way', {'db/a.c': A_CALLS_B, 'db/b.c': B_ALONE,
                   'db/c.c': C_CALLS_A}, 0, 'layout: 0 violation')
expect('render', {'online/render/a.c': A_CALLS_B,
                  'online/render/b.c': B_CALLS_A}, 1,
       'online/render: call circle a -> b -> a')
for f in failures:
    print(f)
print(f'layout circles: {len(failures)} failure(s)')
sys.exit(1 if failures else 0)
