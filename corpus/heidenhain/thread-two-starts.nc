%TWO_STARTS.nc
[A two-start thread M30x3 (P1.5), two passes per start, as ncthread writes it.]
[B is one lead (3 mm): the spindle is at C one turn after the pass's start, so at C at the start.]
[C0 and C180 read the same whether C counts with the spindle or against it: no profile needed.]
[Hand-derived: start 1 at 0 deg, start 2 at 180 deg; the passes run from Z5 to Z-30 at lead 3,]
[at D29.6 then D29.2; G0 out to D32 and back to Z5 after each.]
BEARBEITUNG
N10 T1
N20 G97 S800 M3
N30 G0 X29.6 Z5 [start 1, pass 1]
N40 G33 X29.6 Z-30 F3 B3 P3 C0 H0
N50 G0 X32
N60 Z5
N70 X29.6 [start 2, pass 1]
N80 G33 X29.6 Z-30 F3 B3 P3 C180 H0
N90 G0 X32
N100 Z5
N110 X29.2 [start 1, pass 2]
N120 G33 X29.2 Z-30 F3 B3 P3 C0 H0
N130 G0 X32
N140 Z5
N150 X29.2 [start 2, pass 2]
N160 G33 X29.2 Z-30 F3 B3 P3 C180 H0
N170 G0 X32
N180 M5
N190 M30
ENDE
