#!/usr/bin/env python3
"""The shape of src/, as ARCHITECTURE.md states its limits: production functions over 80 lines,
files over 1,500 lines, import cycles between files, snapshot files, and the lines of each
dialect folder.

    python3 scripts/metrics.py          # the figures
    python3 scripts/metrics.py --long   # and every function over 80 lines

Production code is everything outside `#[cfg(test)]` modules (inline, or files named `tests.rs`). A file imports another when a
`use`, a path or a `mod` names an item of it (`crate::…`, `super::…`, `self::…`); a module's
`mod.rs` declaring its children is not an import, nor is a child using its parent's items
(Rust's own tree), but a parent using a child's items is.
"""
import os
import re
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SRC = os.path.join(ROOT, "src")


def files():
    for d, _, fs in os.walk(SRC):
        for f in fs:
            if f.endswith(".rs"):
                yield os.path.join(d, f)


def strip_tests(text):
    """The file without its `#[cfg(test)] mod … { … }` blocks (brace-matched)."""
    out, i = [], 0
    for m in re.finditer(r"#\[cfg\(test\)\]\s*(pub(\([^)]*\))?\s+)?mod\s+\w+\s*\{", text):
        if m.start() < i:
            continue
        out.append(text[i : m.start()])
        depth, j = 1, m.end()
        while j < len(text) and depth:
            depth += {"{": 1, "}": -1}.get(text[j], 0)
            j += 1
        out.append("\n" * text[m.start() : j].count("\n"))
        i = j
    out.append(text[i:])
    return "".join(out)


def blank_literals(text):
    """Strings, chars and comments blanked (newlines kept), so braces in them do not count."""
    out, i, n = [], 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i))
            i = j
        elif text.startswith("/*", i):
            j = text.find("*/", i)
            j = n if j < 0 else j + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif c == "r" and re.match(r'r#*"', text[i:]) and not re.match(r"\w", text[i - 1 : i] or " "):
            hashes = re.match(r'r(#*)"', text[i:]).group(1)
            end = '"' + hashes
            j = text.find(end, i + len(hashes) + 2)
            j = n if j < 0 else j + len(end)
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif c == '"':
            j = i + 1
            while j < n and text[j] != '"':
                j += 2 if text[j] == "\\" else 1
            j += 1
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif c == "'" and re.match(r"'(\\.|[^\\'])'|'\\u\{[0-9a-fA-F]+\}'|'\\x..'", text[i:]):
            m = re.match(r"'(\\.|[^\\'])'|'\\u\{[0-9a-fA-F]+\}'|'\\x..'", text[i:])
            out.append(" " * len(m.group(0)))
            i += len(m.group(0))
        else:
            out.append(c)
            i += 1
    return "".join(out)


def long_functions(path, limit=80):
    text = blank_literals(strip_tests(open(path, encoding="utf-8").read()))
    found = []
    for m in re.finditer(r"\bfn\s+(\w+)", text):
        # the body's opening brace: the first `{` after the signature at nesting 0 of ( and <
        j, depth = m.end(), 0
        while j < len(text):
            ch = text[j]
            if ch in "(":
                depth += 1
            elif ch in ")":
                depth -= 1
            elif ch == ";" and depth == 0:
                j = -1  # a declaration without a body
                break
            elif ch == "{" and depth == 0:
                break
            j += 1
        if j < 0 or j >= len(text):
            continue
        k, d = j + 1, 1
        while k < len(text) and d:
            d += {"{": 1, "}": -1}.get(text[k], 0)
            k += 1
        start = text.count("\n", 0, m.start()) + 1
        end = text.count("\n", 0, k) + 1
        if end - start + 1 > limit:
            found.append((end - start + 1, os.path.relpath(path, ROOT), m.group(1), start))
    return found


def module_of(path):
    rel = os.path.relpath(path, SRC)[:-3].split(os.sep)
    if rel[-1] in ("mod", "lib", "main"):
        rel = rel[:-1]
    return tuple(rel)


def resolve(mods, segs):
    """The file (module) an absolute path of segments lands in: the longest module prefix."""
    for k in range(len(segs), -1, -1):
        if tuple(segs[:k]) in mods:
            return tuple(segs[:k])
    return None


def use_paths(text):
    """Every path used: `use` trees expanded, and `crate::`/`super::`/`self::` paths inline."""
    paths = []
    for m in re.finditer(r"\buse\s+([^;]+);", text):
        tree = re.sub(r"\s+as\s+\w+", "", m.group(1))
        paths.extend(expand(re.sub(r"\s+", "", tree)))
    for m in re.finditer(r"(?<![\w:])((?:crate|super|self|\w+)(?:::\w+)+)", text):
        paths.append(m.group(1))
    return paths


def expand(tree):
    """`a::{b,c::{d,e}}` → [a::b, a::c::d, a::c::e]."""
    i = tree.find("{")
    if i < 0:
        return [tree]
    head, body = tree[:i], tree[i + 1 : tree.rfind("}")]
    parts, depth, cur = [], 0, ""
    for ch in body:
        if ch == "," and depth == 0:
            parts.append(cur)
            cur = ""
            continue
        depth += ch == "{"
        depth -= ch == "}"
        cur += ch
    parts.append(cur)
    out = []
    for p in parts:
        if p:
            out.extend(expand(head + p))
    return out


def graph():
    mods = {}
    for path in files():
        if os.path.basename(path) == "main.rs":
            continue  # the binary: it sits above the library
        mods[module_of(path)] = path
    edges = {m: set() for m in mods}
    for mod, path in mods.items():
        text = blank_literals(strip_tests(open(path, encoding="utf-8").read()))
        for p in use_paths(text):
            segs = p.split("::")
            if segs[0] == "crate":
                segs = segs[1:]
            elif segs[0] in ("super", "self"):
                base = list(mod)
                while segs and segs[0] in ("super", "self"):
                    if segs[0] == "super":
                        base = base[:-1]
                    segs = segs[1:]
                segs = base + segs
            elif segs[0] == "ncthread":
                segs = segs[1:]
            elif mod + (segs[0],) in mods:
                segs = list(mod) + segs  # a child module's path, relative
            else:
                continue
            target = resolve(mods, segs)
            if target is None or target == mod:
                continue
            if mod[: len(target)] == target:
                continue  # a child using its parent's (or an ancestor's) items
            edges[mod].add(target)
    return mods, edges


def cycles(edges):
    """Strongly connected components with more than one file (Tarjan)."""
    index, low, stack, on, out = {}, {}, [], set(), []
    counter = [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in edges[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    sys.setrecursionlimit(10000)
    for v in edges:
        if v not in index:
            visit(v)
    return out


def main():
    # a module's unit tests in a file of their own (`#[cfg(test)] mod tests;`) are not production
    longs = sorted(
        (f for p in files() if os.path.basename(p) != "tests.rs" for f in long_functions(p)),
        reverse=True,
    )
    big = sorted(
        ((sum(1 for _ in open(p, encoding="utf-8")), os.path.relpath(p, ROOT)) for p in files()),
        reverse=True,
    )
    mods, edges = graph()
    circ = cycles(edges)
    snaps = sum(
        1
        for d in ("tests/snapshots", "tests/downstream_snapshots")
        if os.path.isdir(os.path.join(ROOT, d))
        for f in os.listdir(os.path.join(ROOT, d))
        if f.endswith(".snap")
    )
    print(f"production functions over 80 lines: {len(longs)}")
    if "--long" in sys.argv:
        for n, path, name, line in longs:
            print(f"  {n:4} {path}:{line} {name}")
    print(f"files over 1,500 lines: {sum(1 for n, _ in big if n > 1500)}", end="")
    print("".join(f"\n  {n:5} {p}" for n, p in big if n > 1500))
    print(f"import cycles: {len(circ)}")
    for comp in circ:
        print("  " + ", ".join("/".join(m) or "lib" for m in comp))
        for a in comp:
            for b in sorted(edges[a]):
                if b in comp:
                    print(f"    {'/'.join(a) or 'lib'} -> {'/'.join(b) or 'lib'}")
    print(f"snapshot files: {snaps}")
    total = 0
    for d in sorted(os.listdir(os.path.join(SRC, "dialect"))):
        full = os.path.join(SRC, "dialect", d)
        if os.path.isdir(full):
            n = sum(
                sum(1 for _ in open(os.path.join(r, f), encoding="utf-8"))
                for r, _, fs in os.walk(full)
                for f in fs
                if f.endswith(".rs")
            )
            total += n
            print(f"dialect/{d}/: {n} lines")


if __name__ == "__main__":
    main()
