# Regenerates the diagnostic code table in README.md from the code lists: the shared codes in
# src/diag/codes.rs, each dialect's in src/dialect/<id>/codes.rs, in the order that
# dialect::all_codes (src/dialect/mod.rs) lists them.
import os
import re

root = os.path.join(os.path.dirname(__file__), "..")
files = {"crate::diag::codes": "src/diag/codes.rs"}
for d in sorted(os.listdir(os.path.join(root, "src/dialect"))):
    if os.path.exists(os.path.join(root, f"src/dialect/{d}/codes.rs")):
        files[d + "::codes"] = f"src/dialect/{d}/codes.rs"
byname = {}
lists = {}
for module, path in files.items():
    src = open(os.path.join(root, path)).read()
    for m in re.finditer(r'pub const (\w+): Code\s*=\s*(error|warning)\(\s*"(\w+)",\s*"((?:[^"\\]|\\.)*)",?\s*\)', src):
        byname[m.group(1)] = (m.group(3), m.group(2), m.group(4))
    for m in re.finditer(r"pub const (\w+): &\[Code\] = &\[(.*?)\];", src, re.S):
        lists[module + "::" + m.group(1)] = [n.strip() for n in m.group(2).split(",") if n.strip()]
registry = open(os.path.join(root, "src/dialect/mod.rs")).read()
body = re.search(r"\[((?:\s*[\w:]+,)+)\s*\]\s*\.concat\(\)", registry).group(1)
lines = ["| code | default | meaning |", "| --- | --- | --- |"]
for name in [n.strip() for n in body.split(",") if n.strip()]:
    for n in lists[name]:
        i, sev, summ = byname[n]
        lines.append(f"| `{i}` | {sev} | {summ} |")
table = "\n".join(lines) + "\n"
p = os.path.join(root, "README.md")
s = open(p).read()
s = re.sub(r"\| code \| default \| meaning \|\n\| --- \| --- \| --- \|\n(?:\|.*\n)+", table, s)
open(p, "w").write(s)
