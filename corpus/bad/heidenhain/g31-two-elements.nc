%G31TWO.nc
[REFUSED (HEIR011): a succession of threads (a contour of two elements after G31) is not]
[read; each thread needs its own G31. Also refused: G31 without B (the run-in the control]
[would take from the contour or its parameters) and a contour that starts with G1.]
BEARBEITUNG
N10 T9 G97 S1000 M3
N20 G0 X60 Z10
N30 G31 F2 U1.2 B4 P2 IC4
N40 G0 X20 Z0
N50 G1 Z-30
N60 G1 X30 Z-40
N70 G80
N80 G31 F2 U1.2 P2 IC4
N90 G0 X20 Z0
N100 G1 Z-30
N110 G80
N120 G31 F2 U1.2 B4 P2 IC4
N130 G1 X20 Z0
N140 G1 Z-30
N150 G80
N160 M30
ENDE
