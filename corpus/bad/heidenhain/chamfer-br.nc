%BR.nc
[REFUSED: BR, a chamfer or rounding at the block's end point]
BEARBEITUNG
N1 G97 S600 M3
N2 G0 X20 Z2
N3 G95 G1 Z-10 F0.2 BR-1
ENDE
