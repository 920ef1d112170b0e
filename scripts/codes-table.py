# Regenerates the diagnostic code table in README.md from src/diag/codes.rs.
import re
src=open(__import__('os').path.join(__import__('os').path.dirname(__file__), '..', 'src/diag/codes.rs')).read()
# parse const NAME: Code = error("ID", "summary"...) possibly multiline
rows=[]
for m in re.finditer(r'pub const (\w+): Code\s*=\s*(error|warning)\(\s*"(\w+)",\s*"((?:[^"\\]|\\.)*)",?\s*\)', src):
    rows.append((m.group(3), m.group(2), m.group(4)))
order=re.search(r'pub const ALL: &\[Code\] = &\[(.*?)\];', src, re.S).group(1)
names=[n.strip() for n in order.split(',') if n.strip()]
byname={}
for m in re.finditer(r'pub const (\w+): Code\s*=\s*(error|warning)\(\s*"(\w+)",\s*"((?:[^"\\]|\\.)*)",?\s*\)', src):
    byname[m.group(1)]=(m.group(3), m.group(2), m.group(4))
lines=["| code | default | meaning |","| --- | --- | --- |"]
for n in names:
    i,sev,summ=byname[n]
    lines.append(f"| `{i}` | {sev} | {summ} |")
table="\n".join(lines)+"\n"
p=__import__('os').path.join(__import__('os').path.dirname(__file__), '..', 'README.md')
s=open(p).read()
s=re.sub(r'\| code \| default \| meaning \|\n\| --- \| --- \| --- \|\n(?:\|.*\n)+', table, s)
open(p,'w').write(s)
