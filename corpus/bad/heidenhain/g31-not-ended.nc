%G31OPEN.nc
[REFUSED (HEIR011): G31's contour is not ended by G80, so every block after the call was]
[taken for its contour.]
BEARBEITUNG
N10 T9 G97 S1000 M3
N20 G0 X40 Z10
N30 G31 F2 U1.2 B4 P2 IC4
N40 G0 X20 Z0
N50 G1 Z-30
N60 M30
ENDE
