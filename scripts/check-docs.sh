#!/usr/bin/env bash
# Checks the documents and the words of the tree:
# 1. no tracked file speaks of how the work was organised (work-log words:
#    who did a change, in which sitting, under which tracker number); the
#    code and the documents say what is true now and why. The pattern is
#    built from pieces so that this file does not match it.
#    Nor does it cite notes in a scratch folder under /tmp as its sources.
# 2. README.md stays short (under 300 lines): the details live in docs/.
# 3. every relative link in README.md, docs/*.md and samples/README.md
#    names a file or folder of the tree (and a heading there, with #).
# Exits 1 listing every finding.
set -euo pipefail
shopt -s nullglob
cd "$(dirname "$0")/.."
fail=0

h='help''er'
i='iss''ue'
s='sess''ion'
pattern="\\($h|$h h-|$i [0-9]+|\\($i|$s"
if git grep -nIiE "$pattern"; then
  echo "check-docs: the lines above speak of how the work was organised" >&2
  fail=1
fi
# a note in a scratch folder under /tmp is no source for a reader of
# the tree; programs that make their own temporary files name them by a
# pattern (/tmp/satf-...), which this does not match
if git grep -nIE '/tmp/[A-Za-z0-9_.-]+/[A-Za-z0-9_.-]+\.(md|txt|png|exr|json)'; then
  echo "check-docs: the lines above cite scratch files outside the tree" >&2
  fail=1
fi

lines=$(wc -l < README.md)
if [ "$lines" -ge 300 ]; then
  echo "check-docs: README.md has $lines lines (at most 299)" >&2
  fail=1
fi

python3 - README.md docs/*.md samples/README.md <<'EOF' || fail=1
import os, re, sys
link = re.compile(r'\]\(([^)\s]+)(?:\s+"[^"]*")?\)')


def slugs(md):
    """The anchors GitHub gives a file's headings."""
    out = set()
    for line in open(md, encoding='utf-8'):
        m = re.match(r'^#+\s+(.*?)\s*$', line)
        if m:
            text = re.sub(r'[^\w\- ]', '', m.group(1).lower())
            out.add(text.replace(' ', '-'))
    return out


bad = 0
for md in sys.argv[1:]:
    base = os.path.dirname(md)
    for n, line in enumerate(open(md, encoding='utf-8'), 1):
        for target in link.findall(line):
            if re.match(r'^[a-z]+:', target):
                continue
            path, _, anchor = target.partition('#')
            path = os.path.normpath(os.path.join(base, path)) if path else md
            if not os.path.exists(path):
                print(f'{md}:{n}: link to {target}: no such file', file=sys.stderr)
                bad = 1
            elif anchor and path.endswith('.md') and anchor not in slugs(path):
                print(f'{md}:{n}: link to {target}: no such heading', file=sys.stderr)
                bad = 1
sys.exit(bad)
EOF

[ "$fail" = 0 ] && echo "check-docs: words, README length and links fine"
exit "$fail"
