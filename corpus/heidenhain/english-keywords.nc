%ENGLISH.nc
[The section keywords in English, as the English manuals print them (MACHINING, END), and a]
[feed per minute (G94 F mm/min). Hand-derived: G97 1200 rpm; G0 D30 Z1; G1 Z-12 at 150 mm/min;]
[G1 D34 Z-14 at 150 mm/min; G0 D40.]
MACHINING
N10 G97 S1200 M3
N20 G0 X30 Z1
N30 G94 G1 Z-12 F150
N40 X34 Z-14
N50 G0 X40
END
