#!/usr/bin/env python3
"""Checks that the source tree reads as the architecture (README, Layout).

1. Every quoted #include names a public header (satf/NAME.h) or a header in
   the including file's own folder: no file reaches into another library's
   private headers (a tool's folder may use the shared tools/ headers).
2. Public headers are used only along the dependency direction: a library
   includes its own header and those of the libraries below it.
3. Within a folder, the modules (NAME.c with its NAME.h) do not depend on
   each other in a cycle: X depends on Y when X.c or X.h includes Y.h.
4. Within a folder, the files do not call each other in a circle: X.c
   calls Y.c when it names a function (calls it or takes its address) that
   Y.c defines with external linkage. A circle of files calling each other
   reads as one file cut in pieces; the calls between the files of a
   library go one way, as between the libraries.

usage: check-layout.py [ROOT]; exits 1 listing every violation."""
import os
import re
import sys

ROOT = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else
                       os.path.join(os.path.dirname(__file__), '..'))

# folder -> (public headers it owns, public headers it may include)
LIBS = {
    'common': ({'satf', 'common', 'math'}, set()),
    'fiber': ({'fiber'}, {'common'}),
    'db': ({'db'}, {'common', 'fiber'}),
    'offline': ({'offline'}, {'db'}),
    'online/geometry': ({'geometry'}, {'common'}),
    'online/scene': ({'scene'}, {'common'}),
    'online/density': ({'density'}, {'geometry', 'scene', 'db'}),
    'online/import': ({'import'}, {'density'}),
    'online/gl': ({'gl'}, {'common'}),
    'online/render': ({'render'}, {'db', 'density', 'gl'}),
    'tools': (set(), {'offline', 'import', 'render', 'gl'}),
}
PUBLIC_OWNER = {h: lib for lib, (own, _) in LIBS.items() for h in own}
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)


def allowed(lib):
    """Public headers lib may include: its own and everything below."""
    seen, pending = set(), [lib]
    while pending:
        cur = pending.pop()
        own, uses = LIBS[cur]
        for h in own | uses:
            if h not in seen:
                seen.add(h)
                owner = PUBLIC_OWNER.get(h)
                if owner and owner != cur:
                    pending.append(owner)
    return seen


def library_of(rel):
    best = None
    for lib in LIBS:
        if rel.startswith(lib + '/') and (best is None or len(lib) > len(best)):
            best = lib
    return best


def sources():
    for top in list(LIBS) + ['include/satf']:
        base = os.path.join(ROOT, top)
        for dirpath, _, names in os.walk(base):
            for n in names:
                if n.endswith(('.c', '.h', '.cpp')):
                    yield os.path.relpath(os.path.join(dirpath, n), ROOT)


COMMENT = re.compile(r'/\*.*?\*/|//[^\n]*|"(?:\\.|[^"\\\n])*"|'
                     r"'(?:\\.|[^'\\\n])*'", re.S)
# a function definition: at the start of a line, a return type and a name,
# the parameter list, then the body's brace (not a ';': a declaration)
DEFINITION = re.compile(r'^(?!static\b|typedef\b|#)[A-Za-z_][\w \t\*]*?'
                        r'\b([A-Za-z_]\w*)\s*\(([^;{}]*?)\)\s*\{', re.M)
# any function definition, static ones too: a file's own names
ANY_DEFINITION = re.compile(r'^(?!typedef\b|#)[A-Za-z_][\w \t\*]*?'
                            r'\b([A-Za-z_]\w*)\s*\(([^;{}]*?)\)\s*\{', re.M)
IDENT = re.compile(r'\b[A-Za-z_]\w*\b')


def strip(text):
    """The code without comments, string and character literals and
    preprocessor lines (whose names need not be calls)."""
    text = COMMENT.sub(' ', text)
    text = re.sub(r'^\s*#.*?(?<!\\)$', ' ', text, flags=re.M | re.S)
    # a return type on a line of its own joins its function's name
    return re.sub(r'^([A-Za-z_][\w \t\*]*)\n(?=[A-Za-z_]\w*\s*\()', r'\1 ',
                  text, flags=re.M)


def call_edges(files):
    """{stem: set(stems)}: X -> Y when X.c names a function Y.c defines
    with external linkage. files: {path: code without comments}."""
    owner = {}
    for path, code in files.items():
        if path.endswith('.h'):
            continue
        for m in DEFINITION.finditer(code):
            owner.setdefault(m.group(1), set()).add(path)
    edges = {}
    for path, code in files.items():
        if path.endswith('.h'):
            continue
        stem = os.path.splitext(os.path.basename(path))[0]
        own = {m.group(1) for m in ANY_DEFINITION.finditer(code)}
        for name in set(IDENT.findall(code)) - own:
            for other in owner.get(name, ()):
                dep = os.path.splitext(os.path.basename(other))[0]
                if other != path and dep != stem:
                    edges.setdefault(stem, set()).add(dep)
    return edges


def cycles(graph):
    """Each circle of graph ({node: set(nodes)}) once, as a list of nodes
    that ends where it starts."""
    found, state = [], {}

    def visit(node, path):
        state[node] = 1
        for dep in sorted(graph.get(node, ())):
            if state.get(dep) == 1:
                found.append(path[path.index(dep):] + [dep])
            elif dep not in state:
                visit(dep, path + [dep])
        state[node] = 2

    for node in sorted(graph):
        if node not in state:
            visit(node, [node])
    return found


def main():
    errors = []
    code = {}  # folder -> {path: code without comments}
    modules = {}  # folder -> {module: set(modules it includes)}
    for rel in sorted(set(sources())):
        with open(os.path.join(ROOT, rel), encoding='utf-8') as f:
            text = f.read()
        folder = os.path.dirname(rel)
        if not rel.startswith('include/'):
            code.setdefault(folder, {})[rel] = strip(text)
        lib = library_of(rel) if not rel.startswith('include/') else None
        ok = allowed(lib) if lib else None
        stem = os.path.splitext(os.path.basename(rel))[0]
        for inc in INCLUDE.findall(text):
            if inc.startswith('satf/'):
                name = os.path.splitext(inc[5:])[0]
                if name not in PUBLIC_OWNER:
                    errors.append(f'{rel}: includes unknown public header {inc}')
                elif ok is not None and name not in ok:
                    errors.append(f'{rel}: {lib} may not depend on {inc} '
                                  f'(owned by {PUBLIC_OWNER[name]})')
            elif '/' in inc:
                errors.append(f'{rel}: includes {inc} across folders')
            elif not (os.path.exists(os.path.join(ROOT, folder, inc)) or
                      (lib and os.path.exists(os.path.join(ROOT, lib, inc)))):
                errors.append(f'{rel}: includes {inc}, not in its library')
            else:
                dep = os.path.splitext(inc)[0]
                if dep != stem:
                    modules.setdefault(folder, {}).setdefault(stem, set()).add(dep)
    for folder in sorted(modules):
        for cycle in cycles(modules[folder]):
            errors.append(f'{folder}: include cycle ' + ' -> '.join(cycle))
    for folder in sorted(code):
        for cycle in cycles(call_edges(code[folder])):
            errors.append(f'{folder}: call circle ' + ' -> '.join(cycle))
    for e in errors:
        print(e)
    print(f'layout: {len(errors)} violation(s)')
    return 1 if errors else 0


if __name__ == '__main__':
    sys.exit(main())
