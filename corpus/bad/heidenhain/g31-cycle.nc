%G31.nc
[REFUSED: the G31 thread cycle (its passes' infeed and start order are published as prose)]
BEARBEITUNG
N1 T9 G97 S1000 M3
N2 G0 X16 Z4
N3 G31 X16 Z-20 F1.5 U-0.92 I0.3
ENDE
